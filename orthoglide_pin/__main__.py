"""``python -m orthoglide_pin``: the ``orthoglide`` command line."""

from orthoglide_pin.cli import main

raise SystemExit(main())
