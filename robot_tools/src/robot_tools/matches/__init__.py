"""Matches: one simulated match from start cord to report, many on a Dask cluster with a row of
figures each, their run folders, and the scoreboard against the targets."""
