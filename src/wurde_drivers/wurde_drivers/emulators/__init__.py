"""Device emulators that speak each device's real byte protocol over a pseudo-terminal (serial
devices) or a python-can virtual bus (CAN devices), for tests and for trying a config without the
hardware."""
