"""The shipped operators (WURDE guide 7.2.3): ImageWriter, ImagePublisher, StereoDataCollector.

Registered as entry points of group ``wurde.vision_operators`` (setup.py), so the module imports
only the ones its configuration uses.
"""
