"""The Directed Perception PTU-46 pan/tilt unit: codec, device layer, emulator, config reader and
the ``ptu_server`` and ``ptu_emulator`` programs (WURDE 7.4)."""
