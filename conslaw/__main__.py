"""``python -m conslaw``: the ``conslaw`` command (:func:`conslaw.cli.console_main`)."""

import sys

from conslaw.cli import console_main

sys.exit(console_main())
