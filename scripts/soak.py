#!/usr/bin/env python3
"""The `soak` command: robot_tools.chaos.soak.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.chaos.soak import main

if __name__ == '__main__':
    sys.exit(main())
