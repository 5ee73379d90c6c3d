#!/usr/bin/env python3
"""The `run_match` command: robot_tools.matches.run_match.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.matches.run_match import main

if __name__ == '__main__':
    sys.exit(main())
