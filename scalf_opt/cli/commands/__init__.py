"""The commands of ``scalf-opt``, one module each.

A command module has ``NAME``, ``HELP``, ``add_arguments(parser)`` and ``run(args) -> exit code``;
it imports the heavy parts of the package inside ``run``. A new command is a new module and one
entry in :data:`COMMANDS`.
"""

from scalf_opt.cli.commands import (
    analyze_log,
    evaluate,
    export,
    figures,
    gait,
    model,
    optimize,
    paper,
    simulate,
    study,
    variant,
    view,
)

COMMANDS = (
    model,
    evaluate,
    optimize,
    paper,
    view,
    figures,
    simulate,
    export,
    analyze_log,
    variant,
    study,
    gait,
)
"""In the order ``scalf-opt --help`` lists them."""
