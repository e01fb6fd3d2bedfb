"""``python -m scalf_opt.cli``: the same as the ``scalf-opt`` command."""

import sys

from scalf_opt.cli.app import main

sys.exit(main())
