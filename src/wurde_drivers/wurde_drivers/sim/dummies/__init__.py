"""The dummy modules of the simulated Pluto robot (Pluto 5): ``dummy_base``, ``dummy_sick``,
``dummy_wrist``, ``dummy_dmu``, ``dummy_gps``, one WURDE module (one CommsManager) each.

They publish through the same streams (:mod:`wurde_drivers.streams`) as the real drivers, so
configuration alone chooses between a dummy and the device.
"""
