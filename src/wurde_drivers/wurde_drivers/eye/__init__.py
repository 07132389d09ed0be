"""WURDE's Eye (guide 7.8): shows the images of an ImageTransport stream in a window or on a
local web page (:mod:`.module`); the frame source both displays share (:mod:`.frames`), the
window (:mod:`.window`), the page (:mod:`.web`) and the display status (:mod:`.status`)."""
