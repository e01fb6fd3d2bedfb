"""The commands of ``scalf-opt``, one module each.

A command module has ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> exit code``;
it imports the heavy parts of the package inside ``run``. A new command is a new module and one
entry in :data:`COMMANDS`.
"""

from scalf_opt.cli.commands import evaluate, model, optimize, paper, study, variant

COMMANDS = (model, evaluate, optimize, paper, variant, study)
"""In the order ``scalf-opt --help`` lists them."""
