"""Read a URDF as untrusted input: bounded size, UTF-8, hardened XML, finite and physical numbers.

URDFs come from the internet. Before Pinocchio or yourdfpy see one, it is read here:

* at most :data:`MAX_URDF_BYTES` bytes, decoded as UTF-8;
* parsed by ``defusedxml`` with document type declarations forbidden, so no entity can expand
  (an entity-expansion bomb) or pull in another file's content (a ``file://`` external entity);
* every number in ``<inertial>`` and joint ``<limit>`` elements must be finite, masses must not be
  negative, and a revolute or prismatic joint's limits must be finite with lower <= upper.

The text that passed is what Pinocchio parses (``pin.buildModelFromXML``), so nothing else is
read from disk behind the check.
"""

from __future__ import annotations

import math
from pathlib import Path
from xml.etree.ElementTree import Element, ParseError

import defusedxml
from defusedxml.ElementTree import fromstring

from scalf_opt.errors import ModelError

MAX_URDF_BYTES = 20 * 1024 * 1024
"""Largest URDF accepted [bytes] (the largest robot URDF in example-robot-data is ~70 kB)."""

_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_LIMITED_JOINTS = ("revolute", "prismatic")


def _number(path: Path, where: str, text: str | None) -> float:
    try:
        value = float(text) if text is not None else math.nan
    except ValueError:
        raise ModelError(f"{path}: {where} = {text!r} is not a number") from None
    if not math.isfinite(value):
        raise ModelError(f"{path}: {where} = {text!r} is not a finite number")
    return value


def _check_links(path: Path, root: Element) -> None:
    for link in root.iter("link"):
        name = link.get("name", "?")
        inertial = link.find("inertial")
        if inertial is None:
            continue
        mass = inertial.find("mass")
        value = _number(
            path, f"link {name!r} mass", mass.get("value") if mass is not None else None
        )
        if value < 0:
            raise ModelError(f"{path}: link {name!r} mass = {value:g} kg is negative")
        inertia = inertial.find("inertia")
        if inertia is not None:
            for key in _INERTIA_KEYS:
                _number(path, f"link {name!r} inertia {key}", inertia.get(key, "0"))
        origin = inertial.find("origin")
        if origin is not None:
            for key in ("xyz", "rpy"):
                for part in origin.get(key, "0 0 0").split():
                    _number(path, f"link {name!r} inertial origin {key}", part)


def _check_joints(path: Path, root: Element) -> None:
    for joint in root.iter("joint"):
        name, kind = joint.get("name", "?"), joint.get("type", "?")
        limit = joint.find("limit")
        if limit is None or kind not in _LIMITED_JOINTS:
            continue
        lower = _number(path, f"joint {name!r} limit lower", limit.get("lower", "0"))
        upper = _number(path, f"joint {name!r} limit upper", limit.get("upper", "0"))
        if lower > upper:
            raise ModelError(
                f"{path}: joint {name!r} limit lower = {lower:g} is above upper = {upper:g}"
            )
        for key in ("effort", "velocity"):
            if key in limit.attrib:
                _number(path, f"joint {name!r} limit {key}", limit.get(key))


def read_urdf_text(path: str | Path) -> str:
    """The text of a URDF file that passed the checks above.

    Raises:
        ModelError: Missing, too large, not UTF-8, not well-formed, with a DTD or entities, not a
            ``<robot>``, or with a non-finite or unphysical number; the message names the file
            and the element.
    """
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"{path}: URDF file not found")
    size = path.stat().st_size
    if size > MAX_URDF_BYTES:
        raise ModelError(
            f"{path}: URDF file of {size} bytes is larger than the {MAX_URDF_BYTES} allowed"
        )
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text (byte {exc.start})") from exc
    try:
        root = fromstring(data, forbid_dtd=True)
    except defusedxml.DefusedXmlException as exc:
        raise ModelError(
            f"{path}: document type declarations and entities are not allowed in a URDF "
            f"({type(exc).__name__})"
        ) from exc
    except ParseError as exc:
        raise ModelError(f"{path}: not well-formed XML ({exc})") from exc
    if root.tag != "robot":
        raise ModelError(f"{path}: the root element is <{root.tag}>, not <robot>")
    _check_links(path, root)
    _check_joints(path, root)
    return text
