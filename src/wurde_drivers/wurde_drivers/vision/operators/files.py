"""Where the writing operators put their files: ``imageDir`` (default: the WURDE data directory)
and ``imagePrefix`` (default: the operator's name), as guide 7.2.3 gives them for both the
ImageWriter and the StereoDataCollector."""

from __future__ import annotations

import os

import cv2
import numpy as np
from numpy.typing import NDArray

from wurde_idl.errors import ConfigError

from ..operator import Operator

__all__ = ['output_place', 'write_image', 'write_text']


def output_place(operator: Operator) -> tuple[str, str]:
    """``(directory, prefix)`` of ``operator``; the directory is created.

    :raises ConfigError: the directory cannot be created (names the operator's config line).
    """
    directory = os.path.expanduser(operator.options.get('imageDir', '')) or \
        operator.context.data_directory
    prefix = operator.options.get('imagePrefix', '') or operator.name
    try:
        os.makedirs(directory, exist_ok=True)
    except OSError as error:
        raise ConfigError(operator.spec.path, operator.spec.line,
                          f'operator "{operator.name}": imageDir {directory}: {error.strerror}') from error
    return directory, prefix


def _hidden(path: str) -> str:
    """Where a file is written before it takes its name: hidden, same suffix (OpenCV picks the
    format by it), so no reader (a playback camera on the same directory) sees half a file."""
    directory, name = os.path.split(path)
    return os.path.join(directory, '.' + name)


def write_image(path: str, image: NDArray[np.uint8]) -> bool:
    """Write ``image`` to ``path`` whole or not at all; False when it cannot be written."""
    partial = _hidden(path)
    try:
        if not cv2.imwrite(partial, image):
            return False
        os.replace(partial, path)
    except (cv2.error, OSError):
        return False
    return True


def write_text(path: str, text: str) -> bool:
    """Write ``text`` to ``path`` whole or not at all; False when it cannot be written."""
    partial = _hidden(path)
    try:
        with open(partial, 'w') as out:
            out.write(text)
        os.replace(partial, path)
    except OSError:
        return False
    return True
