"""Entry point of `python -m joshua_runtime.dashboard`."""

import sys

from joshua_runtime.dashboard.cli import main

sys.exit(main())
