"""pytest configuration.

The property tests (hypothesis) draw the same examples at every run of the project's test
command: ``scripts/test.sh`` sets ``PENEDGE_SEEDED=1``, so that CI, which gates every change,
never passes or fails by the draw. To explore new examples, run pytest without it (or with
``PENEDGE_SEEDED=0``); the Rust property tests take ``PROPTEST_RNG_SEED`` alike.
"""

import os

try:
    from hypothesis import settings
except ImportError:  # the test extras are not installed: the property tests skip
    settings = None

if settings is not None:
    settings.register_profile("seeded", derandomize=True)
    if os.environ.get("PENEDGE_SEEDED") == "1":
        settings.load_profile("seeded")
