"""Reader of ``camera-config.xml``, the VisionModule's camera file (WURDE guide 7.2.1).

One or more ``<camera name type>`` entities, each with ``<option name value>`` children::

    <camera-config>
      <camera name="DesktopPlayback" type="playback">
        <option name="imageDirectory" value="faceSet"/>
      </camera>
    </camera-config>

Types (guide 7.2.1, plus our simulator's): ``firewire`` (here any OpenCV capture device,
:mod:`.capture`), ``playback`` (logged images, :mod:`.playback`) and ``sim`` (the simulated
robot's eyes). Each type's options are listed in :data:`CAMERA_OPTIONS`; an unknown option, a
missing required one, a duplicate option or camera name is refused with file, line and reason.
Relative paths in options are taken from the config file's directory (:meth:`CameraSpec.path_option`).
Pure Python (lxml).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping

from lxml import etree
from wurde_idl.errors import ConfigError

from ..xml_config import Attributes, children, read_root

__all__ = ['CAMERA_OPTIONS', 'CameraSpec', 'OptionSet', 'load_camera_config']

ROOT_TAG = 'camera-config'


@dataclasses.dataclass(frozen=True)
class OptionSet:
    """The options a camera type takes: ``required`` ones and ``optional`` ones with defaults,
    and the kind of value of those that are not text (``int``, ``number``, ``bool``)."""

    required: tuple[str, ...] = ()
    optional: Mapping[str, str] = dataclasses.field(default_factory=dict)
    kinds: Mapping[str, str] = dataclasses.field(default_factory=dict)

    @property
    def names(self) -> tuple[str, ...]:
        return (*self.required, *self.optional)


#: The firewire camera's picture controls (guide 7.2.1), every one an integer but autoiris.
FIREWIRE_CONTROLS = ('brightness', 'exposure', 'sharpness', 'hue', 'saturation', 'gamma', 'shutter',
                     'gain', 'iris', 'focus', 'zoom')

#: Options of each camera type. The guide's, then ours (``width``, ``height``, ``frameRate``,
#: ``loop``, the sim camera's), with defaults ('' = not set).
CAMERA_OPTIONS: dict[str, OptionSet] = {
    'firewire': OptionSet(('id',), {**{name: '' for name in FIREWIRE_CONTROLS}, 'autoiris': '',
                                    'width': '', 'height': '', 'frameRate': ''},
                          {**{name: 'int' for name in FIREWIRE_CONTROLS}, 'autoiris': 'bool',
                           'width': 'int', 'height': 'int', 'frameRate': 'number'}),
    'playback': OptionSet(('imageDirectory',), {'imageSuffix': '.ppm', 'imagePrefix': '',
                                                'imageDevice': '', 'frameRate': '10', 'loop': 'false'},
                          {'frameRate': 'number', 'loop': 'bool'}),
    'sim': OptionSet((), {'simConfig': 'sim-config.xml', 'truth': '', 'width': '320',
                          'height': '240', 'frameRate': '10', 'fieldOfView': '60',
                          'wallHeight': '2.0', 'cameraHeight': '1.0', 'maxRange': '20'},
                     {'width': 'int', 'height': 'int', 'frameRate': 'number', 'fieldOfView': 'number',
                      'wallHeight': 'number', 'cameraHeight': 'number', 'maxRange': 'number'}),
}
_BOOLEANS = ('true', 'false', 'yes', 'no', '1', '0', 'on', 'off')


def _kind_error(kind: str, value: str) -> str | None:
    """Why ``value`` is not of ``kind``, or None when it is."""
    text = value.strip()
    if kind == 'bool':
        return None if text.lower() in _BOOLEANS else 'is not true or false'
    try:
        number = int(text, 0) if kind == 'int' else float(text)
    except ValueError:
        return f'is not {"an integer" if kind == "int" else "a number"}'
    return None if math.isfinite(number) else 'is not finite'


@dataclasses.dataclass(frozen=True)
class CameraSpec:
    """One ``<camera>``: name, type and options (defaults filled in), with where it was read."""

    name: str
    type: str
    options: Mapping[str, str]
    path: str = ''
    line: int | None = None

    def error(self, reason: str) -> ConfigError:
        """A :class:`ConfigError` at this camera's line (a bad option value found later)."""
        return ConfigError(self.path, self.line, f'camera "{self.name}": {reason}')

    def text(self, name: str) -> str:
        return self.options.get(name, '')

    def number(self, name: str, *, minimum: float | None = None, integer: bool = False) -> float:
        """Option ``name`` as a number; :raises ConfigError: naming the camera and option."""
        raw = self.options.get(name, '')
        try:
            value: float = int(raw, 0) if integer else float(raw)
        except ValueError as error:
            kind = 'an integer' if integer else 'a number'
            raise self.error(f'option {name}="{raw}" is not {kind}') from error
        if minimum is not None and not value >= minimum:
            raise self.error(f'option {name}={raw} is below {minimum:g}')
        return value

    def flag(self, name: str) -> bool:
        raw = self.options.get(name, '').strip().lower()
        if raw in ('true', 'yes', '1', 'on'):
            return True
        if raw in ('false', 'no', '0', 'off', ''):
            return False
        raise self.error(f'option {name}="{raw}" is not true or false')

    def path_option(self, name: str) -> str:
        """Option ``name`` as a path; a relative one is taken from the config file's directory."""
        value = os.path.expanduser(self.options.get(name, ''))
        if value and not os.path.isabs(value) and self.path:
            return os.path.join(os.path.dirname(os.path.abspath(self.path)), value)
        return value


def _options(path: str, node: etree._Element, allowed: OptionSet, camera: str) -> dict[str, str]:
    found: dict[str, tuple[str, int | None]] = {}
    for child in children(path, node, ('option',)):
        attrs = Attributes(path, child, required=('name', 'value'))
        name, value = attrs.text('name'), attrs.values['value']
        if name not in allowed.names:
            raise attrs.error(f'camera "{camera}" has no option "{name}"; options: '
                              f'{", ".join(allowed.names)}')
        if name in found:
            raise attrs.error(f'option "{name}" given twice (first on line {found[name][1]})')
        problem = _kind_error(allowed.kinds[name], value) if name in allowed.kinds else None
        if problem:
            raise attrs.error(f'option {name}="{value}" of camera "{camera}" {problem}')
        found[name] = (value, attrs.line)
    missing = [name for name in allowed.required if name not in found]
    if missing:
        raise ConfigError(path, node.sourceline, f'camera "{camera}" needs option(s) {", ".join(missing)}')
    return {**allowed.optional, **{name: value for name, (value, _) in found.items()}}


def _camera(path: str, node: etree._Element) -> CameraSpec:
    attrs = Attributes(path, node, required=('name', 'type'))
    name = attrs.text('name')
    kind = attrs.choice('type', tuple(CAMERA_OPTIONS))
    return CameraSpec(name, kind, _options(path, node, CAMERA_OPTIONS[kind], name), path, attrs.line)


def load_camera_config(path: str | os.PathLike[str]) -> dict[str, CameraSpec]:
    """Every camera of the file by name, in file order.

    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element,
        attribute, type or option, a missing required one, duplicates, no camera at all.
    """
    path = os.fspath(path)
    root = read_root(path, ROOT_TAG)
    cameras: dict[str, CameraSpec] = {}
    for node in children(path, root, ('camera',)):
        camera = _camera(path, node)
        if camera.name in cameras:
            raise ConfigError(path, node.sourceline, f'duplicate camera name "{camera.name}" '
                                                     f'(first on line {cameras[camera.name].line})')
        cameras[camera.name] = camera
    if not cameras:
        raise ConfigError(path, root.sourceline, f'<{ROOT_TAG}> holds no <camera>')
    return cameras
