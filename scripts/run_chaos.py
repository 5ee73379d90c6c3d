#!/usr/bin/env python3
"""The `run_chaos` command: robot_tools.chaos.run_chaos.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.chaos.run_chaos import main

if __name__ == '__main__':
    sys.exit(main())
