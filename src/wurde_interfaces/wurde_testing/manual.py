"""The README and the manual (``docs/*.md``) as the tests read them.

Every runnable example of the README and the manual is marked ``<!-- example: NAME -->`` right
before its fenced block, and a test runs it as printed.  The tests find an example by its name,
wherever the text that holds it lives, so moving a section from one page to another (issue 40 moved
the README's manual into ``docs/``) changes no test.  A name must appear once in the whole manual:
two examples of one name would leave the test running only one of them.
"""

from __future__ import annotations

import os
import pathlib
import re
import textwrap

MARKER = re.compile(r'^ *<!-- example: ([\w-]+) -->', re.M)
HEADING = re.compile(r'^(#{1,6}) (.+?)\s*$')
FENCE = re.compile(r'^\s*```')


def repository_root() -> pathlib.Path:
    """The workspace's root: the first directory above this file that holds README.md and docs/
    (``install/`` lives inside it), else ``$WURDE_ROOT`` (set by ``env.sh``)."""
    for directory in pathlib.Path(__file__).resolve().parents:
        if (directory / 'README.md').is_file() and (directory / 'docs' / 'index.md').is_file():
            return directory
    if os.environ.get('WURDE_ROOT'):
        return pathlib.Path(os.environ['WURDE_ROOT'])
    raise FileNotFoundError(f'no workspace (README.md beside docs/index.md) above {__file__}')


def pages(root: pathlib.Path | None = None) -> list[pathlib.Path]:
    """README.md first, then every page of ``docs/``, sorted."""
    root = root or repository_root()
    return [root / 'README.md', *sorted((root / 'docs').glob('*.md'))]


def example(name: str, language: str, root: pathlib.Path | None = None) -> str:
    """The code of example ``name``: the first ```language block after its marker, dedented when
    the block sits in a list item.  Fails unless the name is marked exactly once."""
    found = []
    for page in pages(root):
        text = page.read_text()
        for match in MARKER.finditer(text):
            if match.group(1) == name:
                found.append((page, text, match.end()))
    where = ', '.join(str(page.name) for page, _, _ in found)
    assert len(found) == 1, f'example {name!r} is marked {len(found)} times (in: {where or "no page"})'
    page, text, start = found[0]
    block = re.compile(rf'^( *)```{re.escape(language)}\n(.*?)^\1```', re.S | re.M).search(text, start)
    assert block, f'{page.name}: no ```{language} block after the example {name!r}'
    return textwrap.dedent(block.group(2))


def examples(language: str, root: pathlib.Path | None = None) -> dict[str, str]:
    """Every marked example whose block (the first fence after its marker) is in ``language``."""
    names = []
    for page in pages(root):
        text = page.read_text()
        for match in MARKER.finditer(text):
            fence = re.compile(r'^ *```(\w*)\n', re.M).search(text, match.end())
            if fence and fence.group(1) == language:
                names.append(match.group(1))
    return {name: example(name, language, root) for name in names}


def headings(text: str) -> list[tuple[int, int, str]]:
    """(line index, level, title) of every Markdown heading outside fenced code."""
    found, inside = [], False
    for index, line in enumerate(text.splitlines()):
        if FENCE.match(line):
            inside = not inside
            continue
        heading = None if inside else HEADING.match(line)
        if heading:
            found.append((index, len(heading.group(1)), heading.group(2)))
    return found


def section(title: str, root: pathlib.Path | None = None) -> str:
    """The text of the section headed ``title`` (its heading line included, up to the next heading
    of the same or a higher level), on whichever page holds it; the title must be unique."""
    found = []
    for page in pages(root):
        lines = page.read_text().splitlines(keepends=True)
        marks = headings(''.join(lines))
        for position, (index, level, text) in enumerate(marks):
            if text != title:
                continue
            end = next((other for other, other_level, _ in marks[position + 1:] if other_level <= level),
                       len(lines))
            found.append(''.join(lines[index:end]))
    assert len(found) == 1, f'section {title!r} found {len(found)} times in README.md and docs/'
    return found[0]
