"""The WURDE programming model on rclpy: CommsManager, RobotObjects with data / info / request channels, Writable locks, triggers, RoleConfiguration and Logger (issue: wurde_core)."""
