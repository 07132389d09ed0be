"""map_server maps (wurde_idl.gridmap): what is written reads back equal, as map_server reads it
(the grey of unknown cells stays unknown), and maps that are wrong are refused with the file, the
line and the reason."""

from __future__ import annotations

import pathlib

import numpy as np
import pytest

from wurde_idl.errors import MapError
from wurde_idl.gridmap import load_grid_map, save_grid_map


def _cells() -> np.ndarray:
    cells = np.full((4, 6), -1, dtype=np.int8)
    cells[1:3, 1:5] = 0
    cells[0, :] = 100
    cells[3, 2] = 100
    return cells


def test_a_saved_map_reads_back_equal(tmp_path: pathlib.Path) -> None:
    save_grid_map(tmp_path / 'room.yaml', _cells(), origin=(-1.5, 2.0), resolution=0.05)
    loaded = load_grid_map(tmp_path / 'room.yaml')
    assert np.array_equal(loaded.cells, _cells())
    assert loaded.resolution == 0.05 and loaded.origin == (-1.5, 2.0, 0.0)
    text = (tmp_path / 'room.yaml').read_text()
    assert 'image: room.pgm' in text and 'mode: trinary' in text
    image = (tmp_path / 'room.pgm').read_bytes()
    assert image.startswith(b'P5') and image.endswith(bytes([0] * 6))   # row 0 (y = origin) is the image's last


def test_plain_pgm_scale_mode_and_negate_are_read_as_map_server_reads_them(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'm.pgm').write_text('P2\n# a comment\n3 1\n255\n0 128 255\n')
    (tmp_path / 'm.yaml').write_text('image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nmode: scale\n'
                                     'occupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 1\n')
    cells = load_grid_map(tmp_path / 'm.yaml').cells
    assert cells.tolist() == [[0, -1, 100]]                  # negated: 255 is occupied


@pytest.mark.parametrize('text, line, reason', [
    ('image: m.pgm\nresolution: -1\norigin: [0, 0, 0]\n', 2, 'resolution must be positive'),
    ('image: m.pgm\nresolution: 0.05\norigin: [0, 0]\n', 3, 'origin must be a list'),
    ('image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: raw\n', 4, "mode 'raw'"),
    ('image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\ncolour: red\n', 4, "unknown key 'colour'"),
    ('image: m.pgm\nresolution: 0.05\n', None, "missing key 'origin'"),
    ('image: m.pgm\nresolution: [0.05\n', 3, 'not YAML'),
])
def test_a_wrong_yaml_is_refused_with_line_and_reason(tmp_path: pathlib.Path, text: str, line: int | None,
                                                      reason: str) -> None:
    (tmp_path / 'm.pgm').write_bytes(b'P5 1 1 255\n\x00')
    (tmp_path / 'm.yaml').write_text(text)
    with pytest.raises(MapError, match=reason) as caught:
        load_grid_map(tmp_path / 'm.yaml')
    assert caught.value.line == line and caught.value.path.endswith('m.yaml')


@pytest.mark.parametrize('image, reason', [
    (b'\x89PNG\r\n', 'only PGM images'),
    (b'P5 4 4 255\n\x00\x00', 'PGM data truncated'),
    (b'P5 4 x 255\n', 'bad PGM header field'),
])
def test_a_wrong_image_is_refused(tmp_path: pathlib.Path, image: bytes, reason: str) -> None:
    (tmp_path / 'm.pgm').write_bytes(image)
    (tmp_path / 'm.yaml').write_text('image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n')
    with pytest.raises(MapError, match=reason):
        load_grid_map(tmp_path / 'm.yaml')


def test_a_missing_image_names_the_yaml_line(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'm.yaml').write_text('resolution: 0.05\nimage: gone.pgm\norigin: [0, 0, 0]\n')
    with pytest.raises(MapError, match='gone.pgm: cannot be read') as caught:
        load_grid_map(tmp_path / 'm.yaml')
    assert caught.value.line == 2
