"""``python -m gridfield``: the same as the ``gridfield`` command."""

from .cli import main

raise SystemExit(main())
