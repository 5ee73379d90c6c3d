#!/usr/bin/env python3
"""The `run_matches` command: robot_tools.matches.run_matches.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.matches.run_matches import main

if __name__ == '__main__':
    sys.exit(main())
