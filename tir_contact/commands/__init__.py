"""Sub-commands of the ``tir-contact`` CLI, one module each.

Each module provides ``add_parser(subparsers)`` and ``run(args) -> int`` (the exit code).
Heavy imports happen inside ``run`` so that ``tir-contact --help`` stays fast.
"""
