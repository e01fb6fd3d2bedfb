"""The ``scalf-opt`` command line: thin, it parses, calls the API and prints.

Importing it is cheap (no CasADi, Pinocchio or matplotlib): each command imports what it needs
when it runs.
"""

from scalf_opt.cli.app import main

__all__ = ["main"]
