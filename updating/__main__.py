"""``python -m updating`` runs the ``vtcr`` command line."""

import sys

from updating.cli import main

sys.exit(main())
