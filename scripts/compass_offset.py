#!/usr/bin/env python3
"""The `compass_offset` command: robot_tools.calibration.compass_offset.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.calibration.compass_offset import main

if __name__ == '__main__':
    sys.exit(main())
