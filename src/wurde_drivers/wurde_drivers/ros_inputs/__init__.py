"""``ros_inputs``: a live ROS 2 robot's standard topics (LaserScan, Odometry, TF, cmd_vel) as the
WURDE base and laser streams (:mod:`.module`)."""
