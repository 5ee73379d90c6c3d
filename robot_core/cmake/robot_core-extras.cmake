# Included by every package that finds robot_core (find_package(catkin COMPONENTS robot_core)).
# A plain `catkin_make` or `catkin build`, as ROS users type them, gives no build type, and so -O0
# (the filter's update then costs 4x): with none given, build optimised with debug symbols.
if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE RelWithDebInfo)
endif()
