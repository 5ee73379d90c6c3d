"""What every layer shares, the Python side: geometry (the twin of include/robot_core/geometry.h)."""
