"""Device drivers that speak the real protocols (SICK, rFLEX, PTU, CAN wrist, GPS, DMU), their
device emulators, and the simulated Pluto robot (issues: drivers, simulated robot)."""
