"""Sub-commands of the ``tir-contact`` CLI, one module each.

Each module provides ``DESCRIPTION`` (the command's ``--help`` text), ``add_arguments(parser)``
and ``run(args) -> int`` (the exit code); :mod:`tir_contact.cli` registers them from its
table ``COMMANDS``, imports a module only when its command is given, and turns every error
a command raises into one line and an exit code. ``run`` is argparse values in, one call of
a library workflow, a summary out.
"""
