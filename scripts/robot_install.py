#!/usr/bin/env python3
"""The `robot_install` command: robot_tools.install.robot_install.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.install.robot_install import main

if __name__ == '__main__':
    sys.exit(main())
