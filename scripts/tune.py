#!/usr/bin/env python3
"""The `tune` command: robot_tools.tuning.tune.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.tuning.tune import main

if __name__ == '__main__':
    sys.exit(main())
