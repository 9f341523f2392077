"""Exceptions raised by the `assembly` package.

A small hierarchy in one module, as ``networkx/exception.py`` does:

* :class:`AssemblyError` (a :class:`ValueError`) -- an assembly is invalid or is used
  inconsistently, e.g. an unknown joint id passed to ``Case.with_joint_parameters``;
* :class:`DescriptionError` (an :class:`AssemblyError`) -- an assembly description
  (TOML file, text or dict) cannot be read.  It carries *every* problem found in the
  description, one :class:`Issue` per line.
"""

from __future__ import annotations

import difflib
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Union

__all__ = ["CrossReferenceError", "Loc", "AssemblyError", "DescriptionError", "Issue",
           "format_path", "listing", "did_you_mean"]

_PLAIN_KEY = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")


def format_path(loc: Iterable[str | int]) -> str:
    """Format a location tuple as a dotted path with ``[i]`` for list indices.

    Parameters
    ----------
    loc : iterable of str or int
        E.g. pydantic's ``loc`` of an error, ``("joints", "G2", "between", 1)``.

    Returns
    -------
    str
        E.g. ``joints.G2.between[1]``; keys that are not plain ids are quoted as in TOML,
        ``plates."P 1".size``.

    Examples
    --------
    >>> format_path(("joints", "G2", "between", 1))
    'joints.G2.between[1]'
    """
    out = ""
    for item in loc:
        if isinstance(item, int) and not isinstance(item, bool):
            out += f"[{item}]"
            continue
        key = str(item)
        segment = key if key and set(key) <= _PLAIN_KEY else json.dumps(key, ensure_ascii=False)
        out += f".{segment}" if out else segment
    return out


class AssemblyError(ValueError):
    """An assembly is invalid or is used inconsistently."""


@dataclass(frozen=True)
class Issue:
    """One problem of an assembly description.

    Attributes
    ----------
    source : str
        Where the description came from: a file name such as ``cases/x.toml``,
        ``"<string>"`` or ``"<dict>"``.
    path : str
        Dotted path of the offending field with ``[i]`` for list indices, e.g.
        ``joints.G2.between[1]``; ``line 12, column 3`` for a TOML syntax error;
        empty when the problem concerns the whole source (e.g. a missing file).
    message : str
        What is wrong and how to fix it, on one line.
    """

    source: str
    path: str
    message: str

    def __str__(self) -> str:
        """Return the issue as ``source: path: message`` on one line."""
        parts = [self.source, self.path, self.message] if self.path else [self.source, self.message]
        return ": ".join(parts).replace("\n", " ")


class DescriptionError(AssemblyError):
    """An assembly description cannot be read; carries every problem found.

    Parameters
    ----------
    issues : iterable of Issue
        The problems, in the order they are reported.  At least one.

    Attributes
    ----------
    issues : list of Issue
        The problems.
    messages : list of str
        One line per problem, ``source: path: what is wrong; how to fix it``.

    Examples
    --------
    >>> from assembly import load_case_text
    >>> try:
    ...     load_case_text('name = "x"', source="x.toml")
    ... except DescriptionError as err:
    ...     print(err.issues[0].path)
    frequency
    """

    def __init__(self, issues: Iterable[Issue]) -> None:
        self.issues: list[Issue] = list(issues)
        self.messages: list[str] = [str(issue) for issue in self.issues]
        super().__init__("\n".join(self.messages))

    @property
    def source(self) -> str:
        """The source named by the first issue (``""`` if there is none)."""
        return self.issues[0].source if self.issues else ""

    def __str__(self) -> str:
        """Return the messages joined by newlines."""
        return "\n".join(self.messages)


def listing(names: Iterable[str]) -> str:
    """``names`` joined by commas, or ``none``: the choices a message lists."""
    names = list(names)
    return ", ".join(names) if names else "none"


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """`` (did you mean 'X'?)`` for the choice closest to a misspelt ``word``, or nothing."""
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


Loc = tuple[Union[str, int], ...]

class CrossReferenceError(ValueError):
    """Raised by :class:`~assembly.case.Case` validation with every cross-reference problem.

    Attributes
    ----------
    issues : list of (loc, message)
        ``loc`` is a tuple path such as ``("joints", "G2", "between", 1)``.
    """

    def __init__(self, issues: Sequence[tuple[Loc, str]]) -> None:
        self.issues = list(issues)
        super().__init__("\n".join(f"{format_path(loc)}: {msg}" for loc, msg in self.issues))
