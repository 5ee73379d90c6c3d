#!/usr/bin/env python3
"""The `match_report` command: robot_tools.report.match_report.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.report.match_report import main

if __name__ == '__main__':
    sys.exit(main())
