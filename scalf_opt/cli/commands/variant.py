"""``scalf-opt variant``: a robot with scaled legs (lengths, masses) or trunk mass, as a URDF."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from scalf_opt.cli.options import Outputs, add_robot, bounded, load_robot

if TYPE_CHECKING:
    from scalf_opt.model.leg import Leg
    from scalf_opt.model.robot import Robot
    from scalf_opt.robots.variants import VariantScales

MAX_SCALE = 10.0
"""Largest scale of a length or a mass."""

NAME = "variant"
HELP = "derive a URDF with scaled thigh/shank lengths and masses (and its actuator file)"
JSON = True
EXAMPLES = (
    ("scalf-opt variant --thigh-length-scale 1.2 --out long.urdf", "SCalf, 20 % longer thighs"),
    ("scalf-opt variant --robot go1 --trunk-mass-scale 1.5 --out heavy/go1.urdf", "heavier"),
    ("scalf-opt evaluate --urdf long.urdf", "then any command on it (the parent's gait)"),
)

SCALES = (
    ("thigh_length_scale", "thigh length (hip-pitch axis to knee axis)"),
    ("shank_length_scale", "shank length (knee axis to foot)"),
    ("thigh_mass_scale", "thigh mass"),
    ("shank_mass_scale", "shank mass"),
    ("trunk_mass_scale", "trunk mass and inertia"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    for field, what in SCALES:
        parser.add_argument(
            f"--{field.replace('_', '-')}",
            dest=field,
            type=bounded(float, MAX_SCALE),
            default=1.0,
            metavar="X",
            help=f"scale the {what}, at most {MAX_SCALE:g} (default 1)",
        )
    parser.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="FILE",
        help="the variant's URDF (its files go beside it)",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.files import current_location
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.robots.loading import load_robot as load_path
    from scalf_opt.robots.variants import VariantScales, derive_variant

    scales = VariantScales(**{field: getattr(args, field) for field, _ in SCALES})
    robot = load_robot(args)
    variant = derive_variant(robot, scales, args.out)
    derived = load_path(urdf=current_location(variant.urdf_path))  # staged until the end
    say = args.console.text
    say(
        f"variant of {robot.name} ({robot.urdf_path.name}): "
        + ", ".join(
            f"{field.removesuffix('_scale').replace('_', ' ')} x{getattr(scales, field):g}"
            for field, _ in SCALES
        )
    )
    say("leg   link    length [m]            mass [kg]")
    for leg in ("RF", "LH"):
        old, new = robot.leg(leg), derived.leg(leg)
        for label, a, b, ma, mb in (
            ("thigh", old.thigh_length_m, new.thigh_length_m, *_link_masses(old, new, 0)),
            ("shank", old.shank_length_m, new.shank_length_m, *_link_masses(old, new, 1)),
        ):
            say(f"{leg:5s} {label:6s}  {a:.5f} -> {b:.5f}    {ma:.4f} -> {mb:.4f}")
    gait = default_gait_for(robot)  # a variant walks its parent's (the staged copy knows no parent)
    say(
        f"total mass {robot.total_mass_kg:.3f} -> {derived.total_mass_kg:.3f} kg; the variant "
        f"walks {robot.name}'s default trot (T={gait.period_s:.4g} s, S={gait.step_length_m:.4g} "
        f"m, z0={gait.stance_height_m:.4g} m) unless given a gait"
    )
    say("wrote " + ", ".join(str(p) for p in variant.written))
    args.console.json(_variant_data(args, robot, derived, scales, variant.written))
    return 0


def _variant_data(
    args: argparse.Namespace,
    robot: Robot,
    derived: Robot,
    scales: VariantScales,
    written: tuple[Path, ...],
) -> dict[str, Any]:
    """The ``--json`` of ``variant``: provenance, scales, lengths and masses, files written."""
    from dataclasses import asdict

    from scalf_opt.io.provenance import provenance

    legs = {}
    for leg in ("RF", "LH"):
        old, new = robot.leg(leg), derived.leg(leg)
        legs[leg] = {
            "thigh_length_m": [old.thigh_length_m, new.thigh_length_m],
            "shank_length_m": [old.shank_length_m, new.shank_length_m],
            "thigh_mass_kg": list(_link_masses(old, new, 0)),
            "shank_mass_kg": list(_link_masses(old, new, 1)),
        }
    return {
        "provenance": provenance(robot, args.argv),
        "parent": str(robot.urdf_path),
        "scales": asdict(scales),
        "legs": legs,
        "total_mass_kg": [robot.total_mass_kg, derived.total_mass_kg],
        "written": [str(p) for p in written],
    }


def _link_masses(old: Leg, new: Leg, joint: int) -> tuple[float, float]:
    """Mass moved by the hip-pitch (0) or knee (1) joint, before and after [kg]."""
    return float(old.model.inertias[joint + 1].mass), float(new.model.inertias[joint + 1].mass)


def outputs(args: argparse.Namespace) -> Outputs:
    """The variant's URDF and the files that may go beside it, moved into place together."""
    from scalf_opt.actuators.sidecar import sidecar_path_for
    from scalf_opt.model.naming import legs_file_for

    beside = (sidecar_path_for(args.out), legs_file_for(args.out), args.out.with_suffix(".srdf"))
    return Outputs(files={"--out": args.out, **{f"--out ({p.name})": p for p in beside}})
