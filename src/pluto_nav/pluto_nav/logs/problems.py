"""What was wrong with a recording: counted by kind, each kind said once, never a traceback.

Real logs have truncated lines, message types a reader does not know, timestamps that go back and
damaged compression.  A reader reports each problem here: :meth:`LogProblems.skip` counts a line
or message it could not use and warns the first time that kind occurs (with file and line, or bag
and topic), so a log with ten thousand bad lines prints one warning per kind, and the summary
(:meth:`LogProblems.summary`) gives every count.  :class:`LogError` is for a file that cannot be
read at all.
"""

from __future__ import annotations

import collections
import sys
from collections.abc import Callable

from wurde_idl.errors import WurdeError

__all__ = ['LogError', 'LogProblems']


class LogError(WurdeError):
    """A recording that cannot be read at all: missing, of no known format, or with nothing usable.
    The message names the file (and the line or topic where that helps)."""


def _stderr(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


class LogProblems:
    """Counts of what a reader skipped, reordered or dropped, by kind; one warning per kind."""

    def __init__(self, warn: Callable[[str], None] | None = None) -> None:
        """No problem counted yet.

        :param warn: where the warnings go, one line each; None: standard error.
        """
        self.warn = warn or _stderr
        self.counts: collections.Counter[str] = collections.Counter()
        self.errors: list[str] = []
        #: What was passed over on purpose (e.g. CARMEN's SYNC lines): counted, never warned.
        self.ignored: collections.Counter[str] = collections.Counter()

    def skip(self, kind: str, where: str, detail: str = '') -> None:
        """One record of ``kind`` was not used; warned the first time only.

        :param kind: what went wrong, e.g. ``truncated FLASER line``, ``unknown type XYZ``; the count's key.
        :param where: ``file:line`` or ``bag:topic``.
        :param detail: more for the warning (e.g. the offending text); empty: none.
        """
        self.counts[kind] += 1
        if self.counts[kind] == 1:
            more = f': {detail}' if detail else ''
            self.warn(f'{where}: {kind}{more} (skipped; further ones counted, not shown)')

    def note(self, kind: str, where: str, detail: str = '') -> None:
        """Something was mended, not skipped (e.g. a record reordered into time): counted, and
        warned the first time.

        :param kind: what was mended; the count's key.
        :param where: ``file:line`` or ``bag:topic``.
        :param detail: more for the warning; empty: none.
        """
        self.counts[kind] += 1
        if self.counts[kind] == 1:
            more = f': {detail}' if detail else ''
            self.warn(f'{where}: {kind}{more} (further ones counted, not shown)')

    def ignore(self, kind: str) -> None:
        """Something a reader passes over on purpose (not a problem): counted, not warned.

        :param kind: what was passed over, e.g. ``SYNC``; the count's key.
        """
        self.ignored[kind] += 1

    def error(self, message: str) -> None:
        """A problem that ends the reading of the file (or of a part of it) early: said at once.

        :param message: the whole message, naming the file (and the line or topic).
        """
        self.errors.append(message)
        self.warn(message)

    def summary(self) -> str:
        """One line: every count, or ``no problems`` (what was ignored follows in brackets)."""
        parts = [f'{n} {kind}' for kind, n in sorted(self.counts.items())]
        parts += [f'error: {e}' for e in self.errors]
        text = '; '.join(parts) if parts else 'no problems'
        if self.ignored:
            text += ' (ignored: ' + ', '.join(f'{n} {k}' for k, n in sorted(self.ignored.items())) + ')'
        return text

    def __bool__(self) -> bool:
        return bool(self.counts or self.errors)
