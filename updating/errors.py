"""The errors of the updating package that reach the user: bad input (files, options), shown as
one line per problem without a traceback (``docs/cli.md``, exit status 2)."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad user input (file, option): one line per problem, shown without a traceback."""

    def __init__(self, lines: str | Iterable[str]) -> None:
        self.lines = [lines] if isinstance(lines, str) else list(lines)
        super().__init__("\n".join(self.lines))
