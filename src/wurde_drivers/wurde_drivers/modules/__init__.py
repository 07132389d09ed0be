"""The executables of wurde_drivers: one WURDE module (one CommsManager) each.

Dummies (``dummy_base``, ``dummy_sick``, ``dummy_wrist``, ``dummy_dmu``, ``dummy_gps``) and drivers
publish through the same streams and interfaces, so configuration alone chooses between them.
"""
