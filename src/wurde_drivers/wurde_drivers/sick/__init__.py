"""The SICK LMS 2xx / PLS laser: codec, device layer, emulator, config reader and the
``sick_server`` and ``sick_emulator`` programs (WURDE 7.5, Pluto 8.1)."""
