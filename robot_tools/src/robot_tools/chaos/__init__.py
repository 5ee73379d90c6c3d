"""Chaos matches: the faults a robot can suffer, their injection into a running match, the
invariants its bag must keep, and the soak that plays many."""
