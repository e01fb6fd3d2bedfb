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
from xml.etree.ElementTree import Element, ParseError, tostring

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


PACKAGE_PREFIX = "package://"


def with_resolved_meshes(urdf: Path, text: str, package_roots: list[Path]) -> str:
    """The URDF text with every ``<mesh filename>`` replaced by the absolute path it resolves to.

    Each reference is checked by :func:`resolve_mesh`; a mesh loader given the result reads no
    file outside the robot's description, whatever its own ``package://`` lookup would do.

    Raises:
        ModelError: A reference leaves its folder or names no file.
    """
    root = fromstring(text.encode("utf-8"), forbid_dtd=True)
    for mesh in root.iter("mesh"):
        mesh.set("filename", str(resolve_mesh(urdf, mesh.get("filename", ""), package_roots)))
    return tostring(root, encoding="unicode")


def resolve_mesh(urdf: Path, filename: str, package_roots: list[Path]) -> Path:
    """The file a mesh reference names, which must stay inside the robot's description.

    A ``package://NAME/rest`` reference resolves to ``rest`` inside a folder ``NAME`` that is
    one of the URDF's ancestors or sits in one of ``package_roots``, and must stay inside that
    folder; any other reference is a path relative to the URDF's folder and must stay inside it.
    Absolute paths and other URI schemes are refused, and ``..`` or symbolic links may not lead
    out: a URDF from the internet must not make scalf-opt read (and embed in a page) a file
    elsewhere on the disk.

    Raises:
        ModelError: The reference leaves its folder, or is of another kind.
    """
    here = urdf.resolve().parent
    if filename.startswith(PACKAGE_PREFIX):
        package, _, rest = filename[len(PACKAGE_PREFIX) :].partition("/")
        candidates = [p for p in (here, *here.parents) if p.name == package]
        candidates += [root / package for root in package_roots if (root / package).is_dir()]
        for folder in candidates:
            target = (folder / rest).resolve()
            if target.is_relative_to(folder.resolve()) and target.is_file():
                return target
        raise ModelError(
            f"{urdf}: mesh {filename!r} is not a file inside a package folder {package!r} "
            "above the URDF or among the known robot descriptions"
        )
    if "://" in filename or Path(filename).is_absolute():
        raise ModelError(
            f"{urdf}: mesh {filename!r}: only paths relative to the URDF's folder and "
            "package:// references are allowed"
        )
    target = (here / filename).resolve()
    if not target.is_relative_to(here):
        raise ModelError(f"{urdf}: mesh {filename!r} leads out of the URDF's folder {here}")
    if not target.is_file():
        raise ModelError(f"{urdf}: mesh {filename!r}: no such file ({target})")
    return target
