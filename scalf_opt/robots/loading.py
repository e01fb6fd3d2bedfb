"""Load a robot by catalog name or from any URDF whose legs follow a known naming convention.

A URDF loaded by path takes the nominal stance height of the robot whose naming it follows (a
SCalf variant stands like SCalf).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from scalf_opt.errors import ModelError
from scalf_opt.model.robot import Robot
from scalf_opt.robots.catalog import CATALOG, entry


def load_robot(name: str | None = None, urdf: str | Path | None = None) -> Robot:
    """Load a robot by catalog ``name`` or from a ``urdf`` file (default: SCalf).

    Raises:
        ModelError: Unknown name; missing or invalid URDF; legs named like no known robot.
    """
    if name is not None and urdf is not None:
        raise ModelError("give a robot name or a URDF path, not both")
    if urdf is None:
        known = entry(name or "scalf")
        srdf = (known.srdf(), known.STANDING_STATE) if known.srdf is not None else None
        return Robot.from_urdf(
            known.urdf(), [known.naming], known.name, known.nominal_stance_height_m, srdf
        )
    robot = Robot.from_urdf(urdf, [e.naming for e in CATALOG.values()])
    return replace(
        robot, nominal_stance_height_m=CATALOG[robot.naming.name].nominal_stance_height_m
    )
