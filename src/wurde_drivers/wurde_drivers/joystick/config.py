"""Reader of ``joystick-config.xml``: which axis and button numbers a program's names mean
(WURDE guide 10.1.6, used by BlindTeleop's ``configureJoystick``)::

    <joystick-config>
      <joystick name="Saitek P990 Dual Analog Pad">
        <axis id="1" name="translate"/>
        <button id="4" name="stop"/>
      </joystick>
    </joystick-config>

- a file holds one or more ``<joystick name>`` (names unique); a program takes the first unless
  told a name;
- ``id`` is the js_event ``number`` (an integer 0 to 255), ``name`` what the program asks for;
  within one joystick no two axes (or two buttons) share an id or a name.

Anything else (unknown element or attribute, a non-integer id such as the appendix's OCR-damaged
``b5``, a duplicate, an empty joystick) is refused with file, line and reason (ConfigError).
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree
from wurde_idl.errors import ConfigError

from ..xml_config import Attributes, children, local_name, read_root

__all__ = ['JoystickLayout', 'layout_named', 'load_joystick_config']

ROOT_TAG = 'joystick-config'


@dataclasses.dataclass(frozen=True)
class JoystickLayout:
    """One ``<joystick>``: names -> js_event numbers, and where it was read."""

    name: str
    axes: dict[str, int]
    buttons: dict[str, int]
    path: str = ''
    line: int | None = None


def _controls(path: str, joystick: etree._Element) -> tuple[dict[str, int], dict[str, int]]:
    found: dict[str, dict[str, int]] = {'axis': {}, 'button': {}}
    lines: dict[tuple[str, str, object], int | None] = {}
    for node in children(path, joystick, ('axis', 'button')):
        tag = local_name(node)
        attrs = Attributes(path, node, required=('id', 'name'))
        number = int(attrs.number('id', integer=True, minimum=0, maximum=255))
        name = attrs.text('name')
        for key, what in (('id', number), ('name', name)):
            first = lines.get((tag, key, what))
            if first is not None:
                raise attrs.error(f'{tag} {key} "{what}" given twice (first on line {first})')
            lines[(tag, key, what)] = node.sourceline
        found[tag][name] = number
    return found['axis'], found['button']


def load_joystick_config(path: str | os.PathLike[str]) -> list[JoystickLayout]:
    """Every joystick of the file, in order.

    :param path: the joystick-config.xml to read.
    :raises ConfigError: naming the file and line (see the module's docstring).
    """
    path = os.fspath(path)
    root = read_root(path, ROOT_TAG)
    layouts: list[JoystickLayout] = []
    for node in children(path, root, ('joystick',)):
        attrs = Attributes(path, node, required=('name',))
        name = attrs.text('name')
        clash = next((layout for layout in layouts if layout.name == name), None)
        if clash is not None:
            raise attrs.error(f'duplicate joystick name "{name}" (first on line {clash.line})')
        axes, buttons = _controls(path, node)
        if not axes and not buttons:
            raise attrs.error(f'<joystick name="{name}"> names no axis and no button')
        layouts.append(JoystickLayout(name, axes, buttons, path, node.sourceline))
    if not layouts:
        raise ConfigError(path, root.sourceline, f'<{ROOT_TAG}> holds no <joystick>')
    return layouts


def layout_named(layouts: list[JoystickLayout], name: str | None = None) -> JoystickLayout:
    """The joystick called ``name``, or the first when ``name`` is None.

    :param layouts: the file's joysticks.
    :param name: the one wanted.
    :raises ConfigError: no joystick has that name (naming the file and the names it has).
    """
    for layout in layouts:
        if name is None or layout.name == name:
            return layout
    names = ', '.join(f'"{layout.name}"' for layout in layouts)
    raise ConfigError(layouts[0].path if layouts else '', None,
                      f'no <joystick> named "{name}" (joysticks: {names})')
