"""The robot computer: the installer of the robot's service, devices and network lock-down."""
