"""The rFLEX base (B21r, ATRV-Jr): codec, robot parameters, device layer, emulator, config reader
and the ``rflex_server`` and ``rflex_emulator`` programs (WURDE 7.6)."""
