"""The Linux joystick (``/dev/input/js*``): the js_event codec, the device reader, the
joystick-config reader, the guide's GameController and the ``joystick_emulator`` program
(WURDE 7.9, 10.1.6)."""
