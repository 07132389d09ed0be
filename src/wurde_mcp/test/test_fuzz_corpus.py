"""Replays the fuzz corpus kept in the repository (``fuzz/corpus/``, grown by ``make fuzz``,
issue 16) through every target: the shipped seeds, what the campaigns found that reached new code,
and every crash reproducer (``crash-*``) they wrote, which fails here until the bug is fixed.
A target may refuse an input only with its documented error type (``fuzz/targets.py``); a
ConfigError must name a file and a reason."""

from __future__ import annotations

import importlib.util
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def _targets():  # the fuzz folder is not a package: load it by path
    spec = importlib.util.spec_from_file_location('wurde_fuzz_targets', ROOT / 'fuzz' / 'targets.py')
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


targets = _targets()


@pytest.mark.parametrize('name', sorted(targets.TARGETS))
def test_every_kept_input_is_decoded_or_refused_as_documented(name: str) -> None:
    target = targets.TARGETS[name]
    inputs = targets.corpus(target)
    assert inputs, f'{name}: no corpus in {targets.CORPUS / name} (python fuzz/run.py --seed)'
    for path in inputs:
        try:
            targets.check(target, path.read_bytes())
        except Exception as error:
            raise AssertionError(f'{name}: {path.name} raised {error!r}') from error


def test_every_target_has_seeds_from_the_codecs_or_shipped_files() -> None:
    seeds = targets.codec_seeds()
    for target in targets.TARGETS.values():
        shipped = [path for pattern in target.seeds for path in ROOT.glob(pattern)]
        assert seeds.get(target.name) or shipped, f'{target.name}: nothing to start a campaign from'
