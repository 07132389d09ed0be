"""The operator base class: what the VisionModule runs on its cameras' frames (WURDE guide 7.2.3).

An operator is a small class. The module builds it from an ``<operator name type>`` entity
(:class:`~wurde_drivers.vision.vision_config.OperatorSpec`), then follows a fixed life cycle
(docs/style.md 5, as py_trees' behaviours):

- ``__init__(spec)``: no I/O; the options are checked against :attr:`Operator.OPTIONS` (unknown
  ones refused with the config's file and line) and the cameras against :attr:`Operator.CAMERAS`;
- :meth:`setup` (``context``: the module's CommsManager, Logger and data directory): open
  files, register streams; may raise;
- :meth:`process` (``frames``: the newest frame of each of the operator's cameras by name, called
  when its first camera, "main", has a new one): must not block;
- :meth:`shutdown`: idempotent, also after a failed setup.

Write one by subclassing and naming it in the vision config's ``type``; the module finds it by an
entry point in group ``wurde.vision_operators`` or in a ``<plugin path>`` module
(:mod:`.registry`)::

    class Counter(Operator):
        OPTIONS = {'every': '10'}

        def process(self, frames):
            if self.main(frames).index % int(self.options['every']) == 0:
                self.context.logger.info_msg(f'{self.name}: frame {self.main(frames).index}')
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, ClassVar

from wurde_idl.errors import ConfigError

from .camera import Frame
from .vision_config import OperatorSpec

__all__ = ['Operator', 'OperatorContext']


@dataclasses.dataclass(frozen=True)
class OperatorContext:
    """What :meth:`Operator.setup` is given: the module's CommsManager (register streams before
    the loop starts), its Logger and the WURDE data directory."""

    manager: Any
    logger: Any
    data_directory: str


class Operator:
    """Base of every operator; see the module docstring."""

    #: Option name -> default (text, as in the config). Options not listed are refused.
    OPTIONS: ClassVar[Mapping[str, str]] = {}
    #: Least and most cameras the operator takes.
    CAMERAS: ClassVar[tuple[int, int]] = (1, 1)

    def __init__(self, spec: OperatorSpec) -> None:
        """:raises ConfigError: an unknown option or a wrong number of cameras (spec's line)."""
        unknown = sorted(set(spec.options) - set(self.OPTIONS))
        if unknown:
            raise spec.error(f'{type(self).__name__} has no option(s) {", ".join(unknown)}; '
                             f'options: {", ".join(self.OPTIONS) or "none"}')
        least, most = self.CAMERAS
        if not least <= len(spec.cameras) <= most:
            raise spec.error(f'{type(self).__name__} takes {least}..{most} cameras, '
                             f'not {len(spec.cameras)}')
        self.spec = spec
        self.name = spec.name
        self.cameras = spec.cameras
        self.options: dict[str, str] = {**self.OPTIONS, **spec.options}
        self.running = True
        self.processed = 0
        self._context: OperatorContext | None = None

    @property
    def context(self) -> OperatorContext:
        if self._context is None:
            raise RuntimeError(f'operator {self.name}: setup() has not run')
        return self._context

    def main(self, frames: Mapping[str, Frame]) -> Frame:
        """The frame of the operator's first camera ("main")."""
        return frames[self.cameras[0]]

    def setup(self, context: OperatorContext) -> None:
        """Connect: keep ``context``; subclasses open what they need (call this first)."""
        self._context = context

    def process(self, frames: Mapping[str, Frame]) -> None:
        """Handle one new frame of the main camera; never blocks."""

    def set_option(self, name: str, value: str) -> None:
        """Change an option at run time (VisionControl's set option) and :meth:`configure` again.

        :raises ConfigError: the operator has no such option or the value is bad.
        """
        if name not in self.OPTIONS:
            raise ConfigError(self.spec.path, self.spec.line, f'{type(self).__name__} has no option {name}')
        old = self.options[name]
        self.options[name] = value
        try:
            self.configure()
        except ConfigError:
            self.options[name] = old
            raise

    def configure(self) -> None:
        """Read :attr:`options` (called by subclasses' setup and by :meth:`set_option`)."""

    def shutdown(self) -> None:
        """Release what setup took; idempotent."""
