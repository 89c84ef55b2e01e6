"""``python -m ifslib``: see `ifslib.cli`."""
import sys

from .cli import main

sys.exit(main())
