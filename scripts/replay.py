#!/usr/bin/env python3
"""The `replay` command: robot_tools.report.replay.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.report.replay import main

if __name__ == '__main__':
    sys.exit(main())
