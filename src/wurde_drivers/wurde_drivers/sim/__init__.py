"""The simulated Pluto robot (Pluto 5, "dummies"): a 2D world of walls, a robot with a base, a sonar
ring, bumpers, a laser, a wrist, a DMU and a GPS.  The world, the raycaster and the device models
are pure numpy (no rclpy, no wurde_core), and so are the random maps and routes of
:mod:`.generate`; the dummy modules (:mod:`.dummies`) and ``tour`` wrap them.  The real drivers
never import this package."""
