#!/usr/bin/env python3
"""The `new_robot` command: robot_tools.new_robot.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.new_robot import main

if __name__ == '__main__':
    sys.exit(main())
