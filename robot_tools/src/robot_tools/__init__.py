"""The team's tools: one module per concern, imported by the commands in scripts/ (thin entry
points) and by the tests. Subpackages: report (a match's bag read, measured and drawn), matches
(one match, many on a cluster, the scoreboard), chaos (faults, invariants, soak), tuning,
calibration, install (the robot computer)."""
