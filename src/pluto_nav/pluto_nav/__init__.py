"""Pluto's localization: localModule with its five pose streams, poseModule, slamModule and the loc proxy."""
