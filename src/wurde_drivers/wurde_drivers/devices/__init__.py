"""Device layers: each driver's protocol logic over a port (SerialLink or a python-can bus); no ROS."""
