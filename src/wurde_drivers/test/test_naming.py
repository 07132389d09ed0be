"""The naming convention of docs/naming.md, checked over every module of wurde_drivers.

A device's classes are named ``<Device><Role>``: ``Device`` (one ``<device>`` of its config file,
in ``config.py``), ``Driver`` (port + codec, in ``device.py``), ``Emulator`` (the fake device
speaking the real bytes, in ``emulator.py``) and ``Module`` (the module's work per loop turn, in
``module.py``).  The names used before the convention stay importable as aliases of the new ones.
No processes, no ROS graph: this only imports the modules.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pathlib
import pkgutil
import re
from types import ModuleType

import pytest

import wurde_drivers

#: The device words, acronyms written as words (docs/naming.md); ``Pty`` is the emulators' port.
DEVICES = ('Ptu', 'Sick', 'RFlex', 'Gps', 'Dmu', 'Wrist', 'Joystick', 'Vision', 'Pty')

#: Role suffix -> the files (last part of the module's name) a class of that role lives in.
ROLES = {
    'Device': ('config',),
    'Driver': ('device',),
    'Emulator': ('emulator', 'pty'),
    'Module': ('module', 'runner'),
}

#: Suffixes the convention replaced: no class of wurde_drivers is named so any more.
RETIRED = ('Server', 'Runner')

#: Old name -> canonical name: the aliases kept so that nothing outside breaks (docs/naming.md).
ALIASES = {
    'PtuServer': 'PtuModule', 'Ptu46': 'PtuDriver', 'Ptu46Emulator': 'PtuEmulator',
    'SickRunner': 'SickModule', 'SickLaser': 'SickDriver', 'LaserDevice': 'SickDevice',
    'RFlexRunner': 'RFlexModule', 'GpsReceiver': 'GpsDriver', 'DmuRunner': 'DmuModule',
    'WristRunner': 'WristModule', 'VisionRunner': 'VisionModule',
    'JoystickDevice': 'JoystickDriver', 'PtyDevice': 'PtyEmulator',
}

#: Every device's role classes under their canonical names (the table of docs/naming.md).
EXPECTED = {
    'ptu': ('PtuDevice', 'PtuDriver', 'PtuEmulator', 'PtuModule'),
    'sick': ('SickDevice', 'SickDriver', 'SickEmulator', 'SickModule'),
    'rflex': ('RFlexDevice', 'RFlexDriver', 'RFlexEmulator', 'RFlexModule'),
    'gps': ('GpsDevice', 'GpsDriver', 'GpsEmulator', 'GpsModule'),
    'dmu': ('DmuDevice', 'DmuDriver', 'DmuEmulator', 'DmuModule'),
    'wrist': ('WristDevice', 'WristDriver', 'WristEmulator', 'WristModule'),
    'joystick': ('JoystickDriver', 'JoystickEmulator'),
    'vision': ('VisionModule',),
}

#: Names spelled as their standard writes them: NMEA 0183 sentence types.
ALL_CAPS = {'GGA', 'RMC'}

#: The guide's and Pluto's program names, installed as printed beside the snake_case names.
SEED_PROGRAMS = {'blindTeleop', 'sickServer', 'sickLaser', 'rFlexServerII', 'rFlexServer',
                 'safePTUserver', 'visionModule'}


def _modules() -> list[ModuleType]:
    names = [info.name for info in pkgutil.walk_packages(wurde_drivers.__path__, 'wurde_drivers.')]
    return [importlib.import_module(name) for name in sorted(names)]


def _classes() -> list[tuple[ModuleType, str, type]]:
    """Every (module, name, class) where the class was defined in that module."""
    return [(module, name, value) for module in _modules() for name, value in vars(module).items()
            if inspect.isclass(value) and value.__module__ == module.__name__]


def _role(name: str) -> str | None:
    return next((suffix for suffix in (*ROLES, *RETIRED) if name.endswith(suffix)), None)


CLASSES = _classes()


def test_every_role_class_follows_the_convention() -> None:
    wrong = []
    for module, name, cls in CLASSES:
        if name != cls.__name__:
            continue  # an alias: checked below
        role = _role(name)
        if role is None:
            continue
        device = name[:-len(role)]
        where = module.__name__.rsplit('.', 1)[-1]
        if role not in ROLES or device not in DEVICES or where not in ROLES[role]:
            wrong.append(f'{module.__name__}.{name}')
    assert wrong == [], 'named against docs/naming.md: ' + ', '.join(wrong)


def test_every_other_name_of_a_class_is_a_listed_alias_of_its_canonical_name() -> None:
    aliases = {name: cls.__name__ for _module, name, cls in CLASSES if name != cls.__name__}
    assert aliases == ALIASES


@pytest.mark.parametrize('old, new', sorted(ALIASES.items()))
def test_an_alias_is_the_same_object_as_the_canonical_name(old: str, new: str) -> None:
    found = [(module, cls) for module, name, cls in CLASSES if name == old]
    assert len(found) == 1, old
    module, cls = found[0]
    assert getattr(module, new) is cls
    exported = getattr(module, '__all__', None)
    if exported is not None and old in exported:
        assert new in exported, f'{module.__name__} exports {old} but not {new}'


@pytest.mark.parametrize('device', sorted(EXPECTED))
def test_each_device_has_its_role_classes_under_the_canonical_names(device: str) -> None:
    defined = {name for module, name, cls in CLASSES
               if module.__name__.startswith(f'wurde_drivers.{device}.') and name == cls.__name__}
    assert set(EXPECTED[device]) <= defined


def test_acronyms_are_words_in_class_names() -> None:
    shouting = sorted({name for _module, name, _cls in CLASSES
                       if re.search('[A-Z]{3,}', name) and name not in ALL_CAPS})
    assert shouting == []


def test_every_executable_is_snake_case_or_a_seed_program_name() -> None:
    setup = pathlib.Path(__file__).resolve().parents[1] / 'setup.py'
    tree = ast.parse(setup.read_text())
    table = next(node.value for node in ast.walk(tree) if isinstance(node, ast.Assign)
                 and any(isinstance(t, ast.Name) and t.id == 'EXECUTABLES' for t in node.targets))
    names = set(ast.literal_eval(table))
    other = sorted(name for name in names - SEED_PROGRAMS if not re.fullmatch('[a-z][a-z0-9_]*', name))
    assert other == []
    assert SEED_PROGRAMS <= names
