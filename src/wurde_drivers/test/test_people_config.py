"""``<person>`` in sim-config.xml: every refusal names the file and the person's line (read without
ROS, and by a real dummy), random walks are drawn the same every time, and config/pluto-people is
config/pluto plus three people who cross the office's corridor and its doors; whatever a
``<person>`` says, reading it gives people or a ConfigError (hypothesis)."""

from __future__ import annotations

import dataclasses
import math
import pathlib
import re
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from people_fixture import ROBOT_RADIUS, START, people_config
from sim_fixture import ROOT
from wurde_idl.errors import ConfigError
from wurde_testing import ChildProcess, find_executable

from wurde_drivers.sim.config import load_sim_config
from wurde_drivers.sim.loading import load_sim
from wurde_drivers.sim.person_config import PERSON_ATTRIBUTES
from wurde_testing.manual import example

#: A good person, to be spoiled one attribute at a time: across the corridor east of the start.
GOOD = 'name="p" points="6,7.5 9,7.5" speed="1" radius="0.25" height="1.7"'

REFUSALS = [
    # What needs no map (sim/person_config.py, sim/config.py).
    ('name="p" points="6,7.5 9,7.5" height="0.45"', {},
     'is 0.45 m tall and laser "PlutoLaser" is 0.5 m above the floor'),
    ('name="p" points="6,7.5 9,7.5" height="0.5"', {}, 'laser "PlutoLaser" is 0.5 m above'),
    ('name="p" points="6,7.5 9,7.5" height="0.25"', {'elements': {'laser': {'mount-z': '0.2'}}},
     'the sonars is 0.3 m above the floor'),
    (GOOD.replace('speed="1"', 'speed="0"'), {}, 'speed=0 of <person> "p" must be in (0, 1.5] m/s'),
    (GOOD.replace('speed="1"', 'speed="1.6"'), {}, 'must be in (0, 1.5] m/s'),
    (GOOD.replace('speed="1"', 'speed="-0.5"'), {}, 'must be in (0, 1.5] m/s'),
    (GOOD.replace('speed="1"', 'speed="fast"'), {}, 'speed="fast" of <person> is not a number'),
    (GOOD + ' colour="red"', {}, 'unknown attribute(s) colour on <person>'),
    ('points="6,7.5 9,7.5"', {}, '<person> needs attribute(s) name'),
    (GOOD + ' random="3"', {}, 'needs either points (a scripted walk) or random'),
    ('name="p" speed="1"', {}, 'needs either points (a scripted walk) or random'),
    (GOOD + ' area="5,7 9,8"', {}, 'area of <person> goes with random'),
    (GOOD + ' width="0.5"', {}, 'a disc (radius) or a box (length and width), not both'),
    ('name="p" points="6,7.5 9,7.5" width="0.5"', {}, 'needs both length and width (only width given)'),
    (GOOD.replace('radius="0.25"', 'radius="0"'), {}, 'radius=0 of <person> must be above 0'),
    (GOOD.replace('height="1.7"', 'height="3.5"'), {}, 'attribute height=3.5 of <person> is above 3.0'),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,7.5"'), {}, 'needs at least 2 points, got 1'),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,7.5 9;7.5"'), {}, '"9;7.5" is not x,y'),
    (GOOD + ' mode="zigzag"', {}, 'mode="zigzag" of <person> must be one of loop, back-and-forth'),
    (GOOD + ' pause="-1"', {}, 'pause=-1 of <person> is below 0.0'),
    ('name="p" random="1"', {}, 'random=1 of <person> is below 2'),
    ('name="p" random="3" area="9,8 7,7"', {}, 'area of <person> "p" is empty'),
    ('name="p" random="3" area="9,8"', {}, 'area of <person> is two corners'),
    # What the walk refuses (sim/walk.py, through sim/crowd.py).
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,7.5 9,7.5 9,7.5"'), {},
     'person "p": points 2 and 3 are the same place'),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,7.5 9,7.5 9,8 6,7.5"'), {},
     'the last point repeats the first: a loop closes by itself'),
    # What needs the map (sim/crowd.py).
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,6.45 9,7.5"'), {},
     'person "p": point 1 (6, 6.45) is 0.15 m from a wall: the body (disc r 0.25 m'),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="6,7.5 6,5"'), {},
     'the leg from (6, 7.5) to (6, 5) passes within 0.25 m of a wall'),
    ('name="p" points="6,6.95 9,6.95" length="1.6" width="0.4" height="1"', {},
     'point 1 (6, 6.95) is 0.65 m from a wall: the body (box 1.6 x 0.4 m, 1 m tall, reaching 0.82 m'),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="3.5,7.6 9,7.5"'), {},
     "point 1 (3.5, 7.6) is within 0.60 m of the robot's start (3, 7.5): the robot (radius 0.35 m)"),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="1,7 6,7"'), {},
     "the leg from (1, 7) to (6, 7) passes the robot's start (3, 7.5)"),
    (GOOD.replace('points="6,7.5 9,7.5"', 'points="25,7.5 9,7.5"'), {},
     "point 1 (25, 7.5) is outside the map's bounds"),
    ('name="p" random="4" area="5.05,0.05 5.2,0.2"', {}, 'no free waypoint 1 of 4 found'),
    ('name="p" random="3" area="30,30 40,40"', {}, "lies outside the map's bounds"),
]


@pytest.mark.parametrize('attributes, edits, reason', REFUSALS)
def test_a_bad_person_is_refused_with_the_file_and_its_line(tmp_path: pathlib.Path, attributes: str,
                                                            edits: dict, reason: str) -> None:
    path, lines = people_config(tmp_path, [f'<person {GOOD.replace("p", "q", 1)}/>',
                                           f'<person {attributes}/>'], **edits)
    with pytest.raises(ConfigError) as error:
        load_sim(str(path))
    assert f'{path}:{lines["q"] + 1}: ' in str(error.value)     # the line after the good person's
    assert reason in str(error.value)


def _line_of(path: pathlib.Path, attributes: str) -> int:
    return next(n for n, text in enumerate(path.read_text().splitlines(), 1) if attributes in text)


def test_two_people_of_one_name_are_refused_at_the_second(tmp_path: pathlib.Path) -> None:
    path, lines = people_config(tmp_path, [f'<person {GOOD}/>', '<!-- -->', f'<person {GOOD}/>'])
    second = _line_of(path, GOOD) + 2
    with pytest.raises(ConfigError, match=f'{path}:{second}: person "p" is defined twice '
                                          fr'\(first at line {second - 2}\)'):
        load_sim_config(path)


@pytest.mark.parametrize('executable, extra', [('dummy_base', []), ('dummy_sick', ['-n', 'PlutoLaser'])])
def test_a_dummy_refuses_a_person_in_a_wall_with_file_and_line(ros_domain: int, tmp_path: pathlib.Path,
                                                                executable: str, extra: list[str]) -> None:
    path, lines = people_config(tmp_path, ['<person name="ghost" points="6,7.5 6,5"/>'])
    with ChildProcess([find_executable('wurde_drivers', executable), '-c', str(path), *extra]) as child:
        assert child.process.wait(timeout=60) == 2
        child.stop()
    assert f'{path}:{lines["ghost"]}: person "ghost": the leg from (6, 7.5) to (6, 5)' in child.stderr


def test_a_random_walk_is_the_same_on_every_read_and_keeps_its_checks(tmp_path: pathlib.Path) -> None:
    person = '<person name="r" random="8" area="4,6.6 19.5,8.4" radius="0.3" pause="1"/>'
    path, _ = people_config(tmp_path / 'a', [person])
    first = load_sim(str(path))[1].people[0].walk
    assert load_sim(str(path))[1].people[0].walk == first          # every process draws the same
    other, _ = people_config(tmp_path / 'b', [person], top={'seed': '2'})
    assert load_sim(str(other))[1].people[0].walk.points != first.points
    config, world, start = load_sim(str(path))
    points = np.array(first.points)
    assert len(points) == 8 and np.all((points >= (4, 6.6)) & (points <= (19.5, 8.4)))
    for a, b in first.legs:                                        # legs of 0.5 m or more, clear
        assert math.dist(a, b) >= 0.5 and not world.segment_blocked(a, b)
        assert min(world.distance_to_nearest_wall(p) for p in (a, b)) > 0.3
    assert min(math.dist(p, START[:2]) for p in first.points) > ROBOT_RADIUS + 0.3


PLUTO = ROOT / 'config' / 'pluto'
PLUTO_PEOPLE = ROOT / 'config' / 'pluto-people'


def test_config_pluto_people_is_config_pluto_plus_three_people_crossing_corridor_and_doors() -> None:
    pluto = load_sim_config(PLUTO / 'sim-config.xml')
    crowded = load_sim_config(PLUTO_PEOPLE / 'sim-config.xml')
    assert dataclasses.replace(crowded, path=pluto.path, people=()) == pluto
    assert (PLUTO_PEOPLE / 'map.xml').resolve() == (PLUTO / 'map.xml').resolve()
    assert not pluto.people
    config, world, start = load_sim(str(PLUTO_PEOPLE / 'sim-config.xml'))
    assert [p.name for p in world.people] == ['ana', 'ben', 'trolley']
    assert {p.body.is_box for p in world.people} == {False, True}
    corridor = (6.3, 8.7)                                         # the office's corridor, y
    for person in world.people:
        legs = person.walk.legs
        assert all(not world.segment_blocked(a, b) for a, b in legs), person.name
        assert person.walk.speed <= 1.5
        ys = [y for _, y in person.walk.points]
        inside = [corridor[0] < y < corridor[1] for y in ys]
        assert any(inside), f'{person.name} never enters the corridor'
        if person.name != 'ben':                                  # ana and the trolley go through doors
            doors = [(a, b) for a, b in legs if (min(a[1], b[1]) < corridor[0] < max(a[1], b[1]))
                     or (min(a[1], b[1]) < corridor[1] < max(a[1], b[1]))]
            assert len(doors) >= 2, f'{person.name} crosses no door'
    ben = world.people[1].walk
    assert ben.points[0] != ben.points[1] and len(ben.points) == 6   # drawn, from the seed


def test_the_readmes_people_walk_the_office(tmp_path: pathlib.Path) -> None:
    """The manual's ``<person>`` example (docs/simulator.md), in config/sim's office: two people, a disc and a box."""
    block = example('people', 'xml')
    people = [' '.join(element.split()) for element in re.findall(r'<person\b.*?/>', block, re.S)]
    path, lines = people_config(tmp_path, people)
    _, world, _ = load_sim(str(path))
    assert [(p.name, p.body.is_box) for p in world.people] == [('ana', False), ('trolley', True)]
    assert world.people[1].walk.mode == 'back-and-forth' and world.people[0].walk.speed == 1.2


ATTRIBUTE_VALUES = st.one_of(
    st.sampled_from(['0', '1', '-1', '0.3', '1.5', '2', '1e308', 'nan', 'inf', '-inf', '0x10', '', ' ',
                     'loop', 'back-and-forth', '6,7.5 9,7.5', '6,7.5', '5,6.7 19,8.3', '1,2,3', ',']),
    st.text(alphabet='0123456789.,- eE', max_size=20))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(values=st.dictionaries(st.sampled_from(PERSON_ATTRIBUTES), ATTRIBUTE_VALUES, max_size=8))
def test_any_person_attributes_give_a_person_or_a_config_error(tmp_path: pathlib.Path,
                                                               values: dict[str, str]) -> None:
    """Whatever a ``<person>`` says, reading it gives people or a ConfigError with the file and
    the person's line: never another exception."""
    attributes = ' '.join(f'{name}={quoteattr(value)}' for name, value in values.items())
    path, _ = people_config(tmp_path / 'fuzz', [f'<person {attributes}/>'])
    line = _line_of(path, '<person ')
    try:
        _, world, _ = load_sim(str(path))
    except ConfigError as error:
        assert str(error).startswith(f'{path}:{line}: '), error
    else:
        assert len(world.people) == 1
