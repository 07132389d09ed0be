"""BlindTeleop: drive the robot with a joystick through the ObstacleAvoider, and point the
pan/tilt unit (WURDE guide 1.1.5, 7.9).  ``drive`` is the printed program's arithmetic,
``program`` the ``blind_teleop`` (``blindTeleop``) module."""
