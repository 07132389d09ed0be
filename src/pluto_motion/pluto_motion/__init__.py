"""Pluto's movement chain: driveModule, avoidModule and motionModule with the Pluto document's
command flags and status codes."""
