"""``python -m assur``: the command line (``import assur`` is light, so Ctrl-C at start-up is caught by main)."""
import sys

from .cli.main import main

if __name__ == "__main__":
    sys.exit(main())
