"""``python -m tir_contact``: same as the ``tir-contact`` console command."""

import sys

from tir_contact.cli import main

if __name__ == "__main__":
    sys.exit(main())
