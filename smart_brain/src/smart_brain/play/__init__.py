"""What a match strategy knows of the table and how it decides, from what the robot senses (no
ROS here: the strategies feed these from their topics, the tests feed them by hand):
  element_tracker  where the game elements are (configured start, then what the camera sees)
  task_cost        which task next: travel, contest, points, and the time it needs against the time left
  blocked_spots    where goals ended BLOCKED: twice about the same spot, move away first
"""
