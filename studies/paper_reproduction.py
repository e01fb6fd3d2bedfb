"""Reproduce the paper's Tables 5 and 6 (the same as `scalf-opt paper`).

python studies/paper_reproduction.py [--out DIR]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from scalf_opt.cli import main as cli_main


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/paper"))
    args = parser.parse_args(argv)
    return cli_main(["paper", "--out", str(args.out)])


if __name__ == "__main__":
    sys.exit(main())
