"""Pluto's CAN wrist (pan/tilt): codec, device layer, emulator on python-can's virtual bus, config
reader and the ``wrist_module`` program (Pluto 8.3)."""
