"""Locate the URDFs of the example-robot-data package, offline.

The PyPI wheel of example-robot-data ships its robots under ``cmeel.prefix/share/
example-robot-data/robots`` inside site-packages and has no Python module, so the directory is
found through the installed distribution's metadata (no network, no hard-coded path).
"""

from __future__ import annotations

from importlib import metadata
from pathlib import Path

from scalf_opt.errors import ModelError

_DISTRIBUTION = "example-robot-data"
_RELATIVE = "cmeel.prefix/share/example-robot-data/robots"


def example_robot_data_dir() -> Path:
    """The ``robots`` directory of the installed example-robot-data package.

    Raises:
        ModelError: The package is not installed or has no robots directory.
    """
    try:
        dist = metadata.distribution(_DISTRIBUTION)
    except metadata.PackageNotFoundError as exc:
        raise ModelError(
            "example-robot-data is not installed (pip install example-robot-data)"
        ) from exc
    direct = Path(str(dist.locate_file(_RELATIVE)))
    if direct.is_dir():
        return direct
    for file in dist.files or []:
        parts = Path(str(file)).parts
        if "robots" in parts and str(file).endswith(".urdf"):
            index = parts.index("robots")
            return Path(str(dist.locate_file(Path(*parts[: index + 1]))))
    raise ModelError(f"example-robot-data {dist.version}: no robots directory found")
