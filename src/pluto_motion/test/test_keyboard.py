"""Keys from a real pseudo-terminal (pluto_motion.keyboard)."""

from __future__ import annotations

import os
import pty
import termios

import pytest

from pluto_motion.keyboard import Keyboard, decode


def test_arrows_and_keys_are_named() -> None:
    assert decode('\x1b[A\x1b[Bx \x1bOC\x1b[D') == ['up', 'down', 'x', 'space', 'right', 'left']


def test_a_sequence_split_between_reads_is_one_key_and_the_terminal_is_restored() -> None:
    master, slave = pty.openpty()
    try:
        with os.fdopen(os.dup(slave)) as stream:
            before = termios.tcgetattr(slave)
            with Keyboard(stream) as keyboard:
                assert not termios.tcgetattr(slave)[3] & termios.ICANON      # cbreak: key by key
                os.write(master, b'q\x1b[')
                assert keyboard.keys(5.0) == ['q']
                os.write(master, b'A')
                assert keyboard.keys(5.0) == ['up']
                assert keyboard.keys(0.0) == []
            assert termios.tcgetattr(slave) == before
    finally:
        os.close(master)
        os.close(slave)


def test_a_keyboard_needs_a_terminal(tmp_path) -> None:
    with open(tmp_path / 'not-a-tty', 'w+') as stream, pytest.raises(OSError, match='not a terminal'):
        Keyboard(stream)
