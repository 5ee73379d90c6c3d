#!/usr/bin/env python3
"""The `scoreboard` command: robot_tools.matches.scoreboard.main (the tools are the Python package robot_tools)."""
import sys

from robot_tools.matches.scoreboard import main

if __name__ == '__main__':
    sys.exit(main())
