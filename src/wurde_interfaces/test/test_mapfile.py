"""The suite's map format as plain data (wurde_idl.mapfile): MapData, exact round trips, refusals
with file and line, and a writer that never writes what its reader would refuse."""

from __future__ import annotations

import math
import pathlib
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import wurde_idl
from wurde_idl.errors import ConfigError, MapError
from wurde_idl.mapfile import (
    Bounds,
    MapData,
    Place,
    load_map_data,
    map_data_from_bytes,
    map_data_to_bytes,
    polygon_area,
    save_map_data,
)

MAPS = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'


def test_the_shipped_office_map_reads_as_plain_data(tmp_path: pathlib.Path) -> None:
    data = load_map_data(MAPS / 'office.xml')
    assert data.name == 'office'
    assert data.bounds == Bounds(0.0, 0.0, 20.0, 15.0)
    assert data.places['start'] == Place(3.0, 7.5, 0.0)
    assert all(type(v) is float for wall in data.walls for v in wall) and len(data.walls) > 10
    assert data.offlimits and all(len(polygon) >= 3 for polygon in data.offlimits)
    save_map_data(data, tmp_path / 'copy.xml')
    again = load_map_data(tmp_path / 'copy.xml')
    assert again == data and list(again.places) == list(data.places)
    save_map_data(again, tmp_path / 'twice.xml')
    assert (tmp_path / 'twice.xml').read_bytes() == (tmp_path / 'copy.xml').read_bytes()


def test_the_docstring_example_loads_and_polylines_become_walls(tmp_path: pathlib.Path) -> None:
    from wurde_idl import mapfile

    text = mapfile.__doc__.split('::\n', 1)[1].split('\n\n', 1)[0]
    data = map_data_from_bytes(text.strip().encode(), 'docstring')
    assert data.name == 'office' and data.places == {'start': (3.0, 7.5, 0.0)}
    # One <wall> plus a closed polyline of four points: four more walls, the last one closing it.
    assert data.walls == ((0, 6.3, 2.05, 6.3), (0, 0, 20, 0), (20, 0, 20, 15), (20, 15, 0, 15),
                          (0, 15, 0, 0))
    assert data.offlimits == (((16, 1), (19, 1), (19, 3), (16, 3)),)


def test_map_data_normalises_its_inputs_and_compares_by_value() -> None:
    data = MapData('m', walls=[[0, 0, 1, 0]], places={'a': [1, 2]}, offlimits=[[[0, 0], [1, 0],
                                                                                [0, 1]]],
                   bounds=[-1, -1, 2, 2])
    assert data.walls == ((0.0, 0.0, 1.0, 0.0),) and isinstance(data.walls[0], tuple)
    assert data.places['a'] == Place(1.0, 2.0, 0.0) and isinstance(data.places['a'], Place)
    assert data.offlimits == (((0.0, 0.0), (1.0, 0.0), (0.0, 1.0)),)
    assert isinstance(data.bounds, Bounds) and data.bounds.contains(2, -1)
    assert data == MapData('m', ((0, 0, 1, 0),), {'a': (1, 2, 0)}, (((0, 0), (1, 0), (0, 1)),),
                           (-1, -1, 2, 2))
    assert data != MapData('m', ((0, 0, 1, 0),))
    with pytest.raises(TypeError):
        hash(data)
    with pytest.raises(ValueError, match='a wall needs 4 numbers'):
        MapData('m', walls=[(0, 0, 1)])


def test_polygon_area_is_signed() -> None:
    square = [(0, 0), (2, 0), (2, 2), (0, 2)]
    assert polygon_area(square) == 4.0
    assert polygon_area(square[::-1]) == -4.0
    assert polygon_area([(0, 0), (1, 1), (2, 2)]) == 0.0


def test_a_map_without_bounds_keeps_none(tmp_path: pathlib.Path) -> None:
    data = MapData('open', walls=[(0, 0, 5, 0)], places={'start': (1, 1, 0)})
    save_map_data(data, tmp_path / 'open.xml')
    assert b'<bounds' not in (tmp_path / 'open.xml').read_bytes()
    assert load_map_data(tmp_path / 'open.xml').bounds is None


def test_a_nameless_map_is_saved_as_unnamed(tmp_path: pathlib.Path) -> None:
    save_map_data(MapData('', walls=[(0, 0, 1, 1)]), tmp_path / 'n.xml')
    assert load_map_data(tmp_path / 'n.xml').name == 'unnamed'


REFUSED = [
    ('zero-length wall', MapData('m', walls=[(1, 1, 1, 1)]), 'zero length'),
    ('place name with a space', MapData('m', places={'my place': (0, 0)}), 'letters, digits'),
    ('not finite', MapData('m', walls=[(0, 0, math.nan, 1)]), 'not finite'),
    ('place outside the bounds', MapData('m', places={'p': (5, 5)}, bounds=(0, 0, 1, 1)),
     'outside the <bounds>'),
    ('flat polygon', MapData('m', offlimits=[[(0, 0), (1, 1), (2, 2)]]), 'zero area'),
    ('empty bounds', MapData('m', bounds=(0, 0, 0, 1)), 'xmin < xmax'),
    ('name with spaces around', MapData(' m '), 'equal'),
]


@pytest.mark.parametrize('data, reason', [case[1:] for case in REFUSED],
                         ids=[case[0] for case in REFUSED])
def test_the_writer_refuses_what_the_reader_would(tmp_path: pathlib.Path, data: MapData,
                                                  reason: str) -> None:
    target = tmp_path / 'refused.xml'
    with pytest.raises(ValueError, match=reason):
        save_map_data(data, target)
    assert list(tmp_path.iterdir()) == []  # neither the file nor a temporary one


def test_refusals_name_file_and_line_and_are_config_errors(tmp_path: pathlib.Path) -> None:
    path = tmp_path / 'bad.xml'
    path.write_text('<?xml version="1.0"?>\n<map name="bad" version="1.0">\n'
                    '  <place name="a" x="1" y="0"/>\n  <place name="a" x="2" y="0"/>\n</map>\n')
    with pytest.raises(MapError) as caught:
        load_map_data(path)
    assert isinstance(caught.value, ConfigError)
    assert (caught.value.path, caught.value.line) == (str(path), 4)
    assert caught.value.reason == 'duplicate place "a" (first on line 3)'
    with pytest.raises(MapError, match=r'^net:3: unknown attribute\(s\) z on <wall>'):
        map_data_from_bytes(b'<?xml version="1.0"?>\n<map name="x" version="1.0">\n'
                            b'<wall x1="0" y1="0" x2="1" y2="0" z="1"/></map>', 'net')
    with pytest.raises(MapError, match=r'^net:1: a DOCTYPE with an internal subset'):
        map_data_from_bytes(b'<!DOCTYPE map [<!ENTITY e "e">]><map name="&e;" version="1.0"/>',
                            'net')


@pytest.mark.process
def test_the_format_is_importable_from_the_package_and_needs_no_numpy() -> None:
    assert wurde_idl.load_map_data is load_map_data and wurde_idl.MapError is MapError
    code = 'import sys, wurde_idl.mapfile; print("numpy" in sys.modules)'
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            timeout=60, check=True)
    assert result.stdout.strip() == 'False'


_coordinate = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
_point = st.tuples(_coordinate, _coordinate)
_wall = st.tuples(_point, _point).filter(lambda ends: ends[0] != ends[1]).map(
    lambda ends: (*ends[0], *ends[1]))
_polygon = st.lists(_point, min_size=3, max_size=6).filter(lambda p: polygon_area(p) != 0.0)
_name = st.from_regex(r'[A-Za-z0-9_][A-Za-z0-9_.\-]{0,8}', fullmatch=True)
_place = st.tuples(_coordinate, _coordinate, st.floats(-10.0, 10.0))


@settings(max_examples=60, deadline=None)
@given(name=_name, walls=st.lists(_wall, max_size=8),
       places=st.dictionaries(_name, _place, max_size=5),
       offlimits=st.lists(_polygon, max_size=3))
def test_any_valid_map_data_round_trips_exactly(name: str, walls: list, places: dict,
                                                offlimits: list) -> None:
    data = MapData(name, walls, places, offlimits)
    again = map_data_from_bytes(map_data_to_bytes(data))
    assert again == data
    assert [repr(v) for w in again.walls for v in w] == [repr(v) for w in data.walls for v in w]
