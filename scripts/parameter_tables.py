#!/usr/bin/env python3
"""The `parameter_tables` command (make docs): robot_tools.docs.parameter_tables.main."""
import sys

from robot_tools.docs.parameter_tables import main

if __name__ == '__main__':
    sys.exit(main())
