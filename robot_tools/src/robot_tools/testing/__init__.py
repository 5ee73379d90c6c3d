"""The test suite's runner (`make test`, `make check`): the test pool and what it knows of each test."""
