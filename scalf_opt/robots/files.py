"""Where the robot files that ship with scalf-opt are, in a wheel and in a source checkout.

The repository keeps them in its top-level ``urdf/`` folder; the wheel maps that folder into the
package as ``scalf_opt/urdf/`` (``pyproject.toml``, ``[tool.setuptools.package-dir]``). An
installed package finds them there; a source checkout or editable install finds ``urdf/`` beside
the package directory.
"""

from __future__ import annotations

from pathlib import Path

from scalf_opt.errors import ModelError

_PACKAGE = Path(__file__).resolve().parent.parent


def robot_files_dir() -> Path:
    """The folder of the shipped URDFs and actuator sidecars.

    Raises:
        ModelError: Neither the installed nor the source-checkout folder exists.
    """
    for candidate in (_PACKAGE / "urdf", _PACKAGE.parent / "urdf"):
        if candidate.is_dir():
            return candidate
    raise ModelError(
        f"robot files not found: looked in {_PACKAGE / 'urdf'} and "
        f"{_PACKAGE.parent / 'urdf'} (reinstall scalf-opt)"
    )


def shipped_file(name: str) -> Path:
    """Path of a shipped robot file, e.g. ``scalf.urdf``.

    Raises:
        ModelError: The file is not there.
    """
    path = robot_files_dir() / name
    if not path.is_file():
        raise ModelError(f"{path}: robot file not found (reinstall scalf-opt)")
    return path
