#!/usr/bin/env python3
"""``make fuzz``: coverage-guided campaigns (atheris, libFuzzer) over every target of
``fuzz/targets.py`` — the codecs, the XML readers, carmen.ini and the xmlServer's parser (issue 16).

    python fuzz/run.py [--seconds S] [--seed] [TARGET ...]

Each target runs ``S`` seconds (default 30) in its own process, starting from its kept corpus
(``fuzz/corpus/<target>/``).  What the campaign finds that reaches new code is merged back into
that folder (libFuzzer's ``-merge=1``: only inputs that add coverage, so it stays small), and a
crash — any exception other than the target's documented error types — is written there as
``crash-<sha1>``, so that ``make test`` (``wurde_mcp/test/test_fuzz_corpus.py``) replays it until
it is fixed.  ``--seed`` (re)writes the starting inputs: shipped configuration files and valid
frames from the codecs' encoders.  Ends with a table (runs, executions per second, coverage, kept
inputs, crashes) and exit status 1 when any target crashed.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import targets  # noqa: E402  (the folder is not a package)

INSTRUMENTED = ('wurde_drivers', 'wurde_idl', 'wurde_mcp', 'wurde_core', 'lxml')
MAX_LEN = 8192
#: The target of a campaign's own process (libFuzzer re-runs this file for a merge).
TARGET_ENV = 'WURDE_FUZZ_TARGET'


def seed() -> int:
    """Write every target's starting inputs into its corpus folder; returns how many are new."""
    written = 0
    found = targets.codec_seeds()
    for target in targets.TARGETS.values():
        inputs = list(found.get(target.name, []))
        for pattern in target.seeds:
            inputs += [path.read_bytes() for path in sorted(targets.ROOT.glob(pattern))]
        folder = targets.CORPUS / target.name
        folder.mkdir(parents=True, exist_ok=True)
        for data in inputs:
            path = folder / f'seed-{hashlib.sha1(data).hexdigest()}'
            if not path.exists():
                path.write_bytes(data)
                written += 1
    return written


def child(name: str, argv: list[str]) -> None:
    """One target's campaign (or merge) in this process, ``argv`` being libFuzzer's flags and
    corpus folders: libFuzzer ends the process.  A merge runs this file again as its own worker
    (hence the target in the environment, :data:`TARGET_ENV`, and the file being executable)."""
    import atheris

    target = targets.TARGETS[name]
    with atheris.instrument_imports(include=list(INSTRUMENTED)):
        for path in targets.corpus(target):             # imports what the target reaches, instrumented
            if not path.name.startswith('crash-'):
                targets.check(target, path.read_bytes())

    def one(data: bytes) -> None:
        targets.check(target, data)

    atheris.Setup([str(pathlib.Path(__file__).resolve()), *argv[1:]], one)
    atheris.Fuzz()


STAT = re.compile(r'^stat::(\w+):\s*(\d+)', re.M)
COVERAGE = re.compile(r'cov: (\d+) ft: (\d+)')


def campaign(name: str, seconds: int) -> dict[str, object]:
    """Run one target's campaign, then merge what it found into the kept corpus; its figures."""
    folder = targets.CORPUS / name
    folder.mkdir(parents=True, exist_ok=True)
    before = {path.name for path in folder.iterdir()}
    me = [str(pathlib.Path(__file__).resolve()), f'-max_len={MAX_LEN}', '-rss_limit_mb=4096',
          '-timeout=10', '-print_final_stats=1']
    env = {**os.environ, TARGET_ENV: name}
    with tempfile.TemporaryDirectory(prefix=f'fuzz-{name}-') as work:
        started = time.monotonic()
        run = subprocess.run([*me, f'-max_total_time={seconds}', f'-artifact_prefix={folder}/crash-',
                              work, str(folder)], capture_output=True, text=True, env=env)
        elapsed = time.monotonic() - started
        merge = subprocess.run([*me, '-merge=1', str(folder), work], capture_output=True, text=True,
                               env=env)
    after = {path.name for path in folder.iterdir()}
    crashes = sorted(n for n in after - before if n.startswith('crash-'))
    stats = {key: int(value) for key, value in STAT.findall(run.stderr)}
    coverage = COVERAGE.findall(run.stderr)
    if crashes or run.returncode != 0 or merge.returncode != 0:
        sys.stderr.write(run.stderr[-4000:] + merge.stderr[-2000:])
    return {'target': name, 'runs': stats.get('number_of_executed_units', 0),
            'per_s': stats.get('average_exec_per_sec', 0), 'cov': coverage[-1][0] if coverage else '-',
            'kept': len(after), 'new': len(after - before) - len(crashes), 'crashes': crashes,
            'seconds': elapsed, 'status': run.returncode}


def main(argv: list[str] | None = None) -> int:
    if os.environ.get(TARGET_ENV):
        child(os.environ[TARGET_ENV], sys.argv)
        return 0
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('names', nargs='*', metavar='TARGET', help='targets (default: all)')
    parser.add_argument('--seconds', type=int, default=30, help='campaign length per target')
    parser.add_argument('--seed', action='store_true', help='write the starting inputs and stop')
    args = parser.parse_args(argv)
    if args.seed:
        print(f'{seed()} new seed inputs in {targets.CORPUS}')
        return 0
    unknown = sorted(set(args.names) - set(targets.TARGETS))
    if unknown:
        parser.error(f'unknown targets {unknown}; known: {sorted(targets.TARGETS)}')
    from rich.console import Console
    from rich.table import Table

    seed()
    console = Console()
    rows = []
    for name in args.names or list(targets.TARGETS):
        with console.status(f'fuzzing {name} for {args.seconds} s'):
            rows.append(campaign(name, args.seconds))
    table = Table('target', 'runs', 'exec/s', 'coverage', 'kept inputs', 'new', 'crashes',
                  title=f'fuzz campaigns, {args.seconds} s each')
    for row in rows:
        table.add_row(str(row['target']), str(row['runs']), str(row['per_s']), str(row['cov']),
                      str(row['kept']), str(row['new']), ', '.join(row['crashes']) or '0')
    console.print(table)
    return 1 if any(row['crashes'] for row in rows) else 0


if __name__ == '__main__':
    sys.exit(main())
