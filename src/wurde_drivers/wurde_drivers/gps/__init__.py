"""The NMEA 0183 GPS: codec, geodesy (WGS-84 local frame), device layer, emulator, config reader
and the ``gps_module`` and ``gps_emulator`` programs (Pluto 8.4)."""
