"""A real screen for the Eye's tests: an Xvfb display whose framebuffer file is the screenshot.
Xvfb comes from Debian (``tools/setup_system.sh`` installs it, and Chromium for :mod:`cdp`); a
test fails, not skips, when it is missing.
"""

from __future__ import annotations

import os
import pathlib
import select
import shutil
import subprocess
import time
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np

XVFB = '/usr/bin/Xvfb'


def need(path: str, package: str) -> str:
    """``path``, or the program of that name on PATH; fails naming the Debian package."""
    if not (os.path.exists(path) or shutil.which(os.path.basename(path))):
        raise AssertionError(f'{path} is missing: run tools/setup_system.sh (Debian package {package})')
    return path if os.path.exists(path) else str(shutil.which(os.path.basename(path)))


@contextmanager
def xvfb(directory: pathlib.Path, size: tuple[int, int] = (800, 600),
         timeout: float = 20.0) -> Iterator[tuple[str, pathlib.Path]]:
    """An Xvfb server on a free display number (``-displayfd``), black root window, 24-bit
    colour, its framebuffer memory-mapped to an XWD file in ``directory``: yields
    ``(DISPLAY, framebuffer file)``. Stopped (and reaped) on leaving."""
    read, write = os.pipe()
    process = subprocess.Popen(
        [need(XVFB, 'xvfb'), '-displayfd', str(write), '-screen', '0', f'{size[0]}x{size[1]}x24',
         '-fbdir', str(directory), '-br', '-nolisten', 'tcp', '-noreset'],
        pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    os.close(write)
    try:
        number = b''
        deadline = time.monotonic() + timeout
        while not number.endswith(b'\n'):
            left = deadline - time.monotonic()
            ready, _, _ = select.select([read], [], [], max(0.0, left))
            chunk = os.read(read, 16) if ready else b''
            if not chunk:
                said = process.stderr.read().decode() if process.poll() is not None else 'running'
                raise AssertionError(f'Xvfb gave no display number within {timeout} s: {said}')
            number += chunk
        yield f':{int(number)}', directory / 'Xvfb_screen0'
    finally:
        os.close(read)
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def read_xwd(path: pathlib.Path) -> np.ndarray:
    """RGB pixels (height, width, 3) of an XWD file of 24/32 bits per pixel (Xvfb's -fbdir)."""
    raw = path.read_bytes()
    header = np.frombuffer(raw[:100], dtype='>u4')
    header_size, version, format_, _depth, width, height = (int(v) for v in header[:6])
    byte_order, bits_per_pixel, bytes_per_line = int(header[7]), int(header[11]), int(header[12])
    masks = [int(m) for m in header[14:17]]
    ncolors = int(header[19])
    assert version == 7 and format_ == 2 and bits_per_pixel == 32, 'not a 32-bit ZPixmap XWD'
    start = header_size + 12 * ncolors
    words = bytes_per_line // 4
    rows = np.frombuffer(raw, dtype='<u4' if byte_order == 0 else '>u4', count=height * words,
                         offset=start).reshape(height, words)[:, :width]
    channels = []
    for mask in masks:
        shift = (mask & -mask).bit_length() - 1
        channels.append(((rows & mask) >> shift).astype(np.uint8))
    return np.stack(channels, axis=-1)
