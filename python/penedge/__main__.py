"""``python -m penedge``: the command line (see :mod:`penedge.cli`)."""

from penedge.cli import main

raise SystemExit(main())
