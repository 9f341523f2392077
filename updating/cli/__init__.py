"""The ``vtcr`` command line (also ``python -m updating``): :func:`main` parses the arguments
(:mod:`updating.cli.parser`) and runs the command (:mod:`updating.cli.commands`).

Bad input exits with status 2 and one line per problem naming the file, the field and the fix;
no traceback (``docs/cli.md``).
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from updating.cli.parser import build_parser

__all__ = ["main", "build_parser"]

SINGLE_THREADED = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
"""BLAS thread settings the command sets to one, unless the user set them: vtcr's dense matrices
are small (hundreds of unknowns), and a multithreaded BLAS spends more in thread start-up and
contention than it gains (measured: the four-plate run 10x slower on 2 cores with the default
threads). A script that imports the library keeps its own settings."""


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``vtcr`` console script; returns the exit status."""
    for variable in SINGLE_THREADED:
        os.environ.setdefault(variable, "1")
    args = build_parser().parse_args(argv)
    # numpy reads the BLAS settings when it loads: the commands, which load it, come after them
    from updating.cli.commands import execute

    return execute(args)
