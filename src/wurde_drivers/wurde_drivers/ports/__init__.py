"""What carries a device's bytes, shared by every serial driver and emulator: the driver's end
(:mod:`.serial_link`, a pyserial port or URL) and the emulator's end (:mod:`.pty`, a
pseudo-terminal).  No ROS here."""
