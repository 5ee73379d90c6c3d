#!/usr/bin/env python3
"""The test pool of `make test` and `make check`: robot_tools.testing.pool.main (run_tests.sh calls it)."""
import sys

from robot_tools.testing.pool import main

if __name__ == '__main__':
    sys.exit(main())
