"""Where the writing operators put their files: ``imageDir`` (default: the WURDE data directory)
and ``imagePrefix`` (default: the operator's name), as guide 7.2.3 gives them for both the
ImageWriter and the StereoDataCollector."""

from __future__ import annotations

import os

from wurde_idl.errors import ConfigError

from ..operator import Operator

__all__ = ['output_place']


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
