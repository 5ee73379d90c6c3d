#!/usr/bin/env python3
"""The `calibrate` command: robot_tools.calibration.calibrate.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.calibration.calibrate import main

if __name__ == '__main__':
    sys.exit(main())
