"""Every document the code, the tests and the README cite is in this repository.

A Markdown file named in a source file, a script, the Makefile or a Markdown page must exist at
the repository's root, beside the citing file, or under ``docs/``; a seed cited by its file name
must be one that ``docs/seeds.md`` lists.
"""
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
MARKDOWN = re.compile(r'(?<![\w./-])((?:[\w-]+/)*[\w-]+\.md)\b')
SEEDS = re.compile(r'\b(wurde-programming-guide|pluto-software-documentation|programming-with-carmen|'
                   r'au-robot-servers-mobotware)\.txt\b')
TEXT = ('.py', '.md', '.sh', '.xml', '.yaml', '.cfg', '')


def _tracked() -> list[pathlib.Path]:
    """The repository's text files (tracked or about to be: untracked but not ignored)."""
    listing = subprocess.run(['git', 'ls-files', '--cached', '--others', '--exclude-standard'],
                             cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    return [ROOT / name for name in listing
            if pathlib.PurePath(name).suffix in TEXT and (ROOT / name).is_file()]


def _resolves(cited: str, source: pathlib.Path) -> bool:
    return any((base / cited).is_file() for base in (ROOT, source.parent, ROOT / 'docs'))


@pytest.mark.process
def test_every_cited_markdown_document_is_in_the_repository():
    missing = []
    for path in _tracked():
        try:
            text = path.read_text()
        except UnicodeDecodeError:
            continue
        for number, line in enumerate(text.splitlines(), 1):
            missing += [f'{path.relative_to(ROOT)}:{number}: {cited}'
                        for cited in MARKDOWN.findall(line) if not _resolves(cited, path)]
    assert not missing, 'cited but not in the repository:\n' + '\n'.join(missing)


@pytest.mark.process
def test_every_seed_cited_by_file_name_is_listed_in_docs_seeds():
    listed = (ROOT / 'docs' / 'seeds.md').read_text()
    cited = {match for path in _tracked() if path.suffix == '.py'
             for match in SEEDS.findall(path.read_text())}
    assert cited, 'no seed is cited by file name: the pattern is wrong'
    assert all(f'{name}.txt' in listed or name in listed for name in cited), cited
