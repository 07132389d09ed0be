"""The Crossbow DMU: codec, device layer, attitude filter, emulator, config reader and the
``dmu_module`` and ``dmu_emulator`` programs (Pluto 8.2)."""
