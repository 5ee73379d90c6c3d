#!/usr/bin/env python3
"""The `soak` command: robot_tools.chaos.soak.main (the tools are the Python package robot_tools)."""
from robot_tools.chaos.soak import main

if __name__ == '__main__':
    main()
