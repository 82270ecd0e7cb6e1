"""``python -m penedge``: the command line (see :mod:`penedge.cli`)."""

import sys

try:
    from penedge.cli import main

    status = main()
except KeyboardInterrupt:
    # A Ctrl-C before the command's own handling (the imports, the parsing) or just after it
    # returned: the same exit status and message as during the run, no traceback.
    print("\npenedge: interrupted", file=sys.stderr)
    status = 130
raise SystemExit(status)
