"""How the dummies and ``tour`` find and read the simulated world: the sim config, its map, the
start pose and the people; a bad config ends the program with status 2 and ``file:line: reason``."""

from __future__ import annotations

from wurde_core import CommsManager
from wurde_idl.errors import ConfigError

from ..module_setup import config_file, exit_on_config_error
from .config import SimConfig, load_sim_config
from .crowd import place_people
from .mapfile import load_map
from .world import World

__all__ = ['load_sim', 'read_sim_config', 'sim_config_path']


def load_sim(path: str) -> tuple[SimConfig, World, tuple[float, float, float]]:
    """The sim config, its world (with the config's people in it, :mod:`.crowd`) and the start pose.

    :param path: the sim-config.xml.
    :returns: the config, the world, and the start (x, y, theta) from a named place or the numbers.
    :raises ConfigError: with file, line and reason (a start place the map lacks among them).
    """
    config = load_sim_config(path)
    world = load_map(config.map_file)
    start = config.start
    if isinstance(start, str):
        if start not in world.places:
            raise ConfigError(path, None, f'start place "{start}" is not in map {config.map_file} '
                                          f'(places: {", ".join(sorted(world.places)) or "none"})')
        place = world.places[start]
        start = (float(place[0]), float(place[1]), float(place[2]))
    if config.people:
        world = world.with_people(place_people(config, world, start))
    return config, world, start


def sim_config_path(manager: CommsManager, argv: list[str], extra_help: str = '') -> str:
    """Parse a dummy's options and return its sim-config path (``-c``, else the config directory's).

    :param manager: the dummy's manager, its options not parsed yet.
    :param argv: the command line, program name first.
    :param extra_help: more lines for ``-h``, after ``-c``'s.
    """
    manager.set_help_string('  -c FILE  sim-config.xml (default: <config dir>/sim-config.xml)' + extra_help)
    opts = manager.parse_options(argv, 'c:')
    return config_file(manager, opts.user.get('c'), 'sim-config.xml')


def read_sim_config(manager: CommsManager, argv: list[str]) -> SimConfig:
    """Parse a dummy's options and read its sim-config; a bad one ends the program with status 2.

    :param manager: the dummy's manager, its options not parsed yet.
    :param argv: the command line, program name first.
    """
    path = sim_config_path(manager, argv)
    try:
        return load_sim_config(path)
    except ConfigError as error:
        raise SystemExit(exit_on_config_error(argv[0], error)) from None
