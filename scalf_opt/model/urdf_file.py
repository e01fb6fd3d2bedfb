"""Read a URDF as untrusted input: bounded size and shape, UTF-8, hardened XML, physical numbers.

URDFs come from the internet. Before Pinocchio or urdfdom see one, it is read here:

* through :func:`~scalf_opt.files.read_untrusted` (a regular file of at most
  :data:`MAX_URDF_BYTES` bytes), decoded as UTF-8;
* streamed once through expat with document type declarations forbidden, so no entity can
  expand (an entity-expansion bomb) or pull in another file's content (a ``file://`` external
  entity), and with at most :data:`MAX_XML_ELEMENTS` elements nested at most
  :data:`MAX_XML_DEPTH` deep: refused as it streams, before a tree is built;
* a robot model's size: at most :data:`MAX_LINKS` links and :data:`MAX_JOINTS` joints, its
  kinematic tree at most :data:`MAX_TREE_DEPTH` joints deep (a 50,000-link chain crashes
  urdfdom's recursive parser; a star of as many links takes gigabytes);
* every number in ``<inertial>`` and joint ``<limit>`` elements must be finite, masses must not be
  negative, and a revolute or prismatic joint's limits must be finite with lower <= upper.

The text that passed is what Pinocchio parses (``pin.buildModelFromXML``), so nothing else is
read from disk behind the check. Mesh references are confined to the robot's description
(:func:`resolve_mesh`), and the meshes are read with a size bound (:func:`with_local_meshes`).
"""

from __future__ import annotations

import math
import os
import posixpath
import stat
from collections.abc import Mapping, Sequence
from pathlib import Path
from xml.etree.ElementTree import Element, ParseError, tostring
from xml.parsers import expat

from defusedxml.ElementTree import fromstring

from scalf_opt.errors import ModelError
from scalf_opt.files import read_untrusted, read_untrusted_text

MAX_URDF_BYTES = 20 * 1024 * 1024
"""Largest URDF accepted [bytes] (the largest robot URDF in example-robot-data is ~210 kB)."""

MAX_SRDF_BYTES = 1024 * 1024
"""Largest SRDF accepted [bytes] (example-robot-data's are below 50 kB)."""

MAX_XML_ELEMENTS = 100_000
"""Most XML elements in a URDF or SRDF (TIAGo dual, the largest published URDF: ~3,000)."""

MAX_XML_DEPTH = 32
"""Deepest nesting of XML elements (a URDF nests about 6 deep)."""

MAX_LINKS = 1000
"""Most links in a robot (example-robot-data's largest: 130)."""

MAX_JOINTS = 1000
"""Most joints in a robot (example-robot-data's largest: 129 in its kinematic tree)."""

MAX_TREE_DEPTH = 100
"""Most joints from the root link to any link (a quadruped's leg: 4 to 6)."""

MAX_MESH_BYTES = 32 * 1024 * 1024
"""Largest mesh file read [bytes] (Go1's trunk, the largest published quadruped mesh: 28.8 MB)."""

MAX_MESHES_BYTES = 48 * 1024 * 1024
"""Most mesh bytes read for one robot [bytes] (Go1, the most among the catalog's robots: 38 MB)."""


class _RefusedError(Exception):
    """Raised from inside expat's callbacks to stop the stream."""


def check_xml_shape(path: Path, data: bytes, kind: str = "URDF") -> None:
    """Stream ``data`` once: no DTD or entity, bounded element count and nesting.

    Raises:
        ModelError: A DTD or entity, too many or too deeply nested elements, or not
            well-formed XML; the message names the file.
    """
    parser = expat.ParserCreate()
    depth = [0, 0]  # current depth, elements seen

    def start(name: str, attributes: dict[str, str]) -> None:
        depth[0] += 1
        depth[1] += 1
        if depth[0] > MAX_XML_DEPTH:
            raise _RefusedError(f"elements nested deeper than the {MAX_XML_DEPTH} allowed")
        if depth[1] > MAX_XML_ELEMENTS:
            raise _RefusedError(f"more than the {MAX_XML_ELEMENTS} XML elements allowed")

    def end(name: str) -> None:
        depth[0] -= 1

    def doctype(*args: object) -> None:
        raise _RefusedError(
            f"document type declarations and entities are not allowed in the {kind} (DTDForbidden)"
        )

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.StartDoctypeDeclHandler = doctype
    parser.EntityDeclHandler = doctype
    try:
        parser.Parse(data, True)
    except _RefusedError as exc:
        raise ModelError(f"{path}: {exc}") from None
    except expat.ExpatError as exc:
        raise ModelError(f"{path}: not well-formed XML ({exc})") from None


def _parse(path: Path, data: bytes, kind: str = "URDF") -> Element:
    check_xml_shape(path, data, kind)
    try:
        return fromstring(data, forbid_dtd=True)
    except ParseError as exc:  # pragma: no cover - expat already parsed it
        raise ModelError(f"{path}: not well-formed XML ({exc})") from exc


def _check_size(path: Path, root: Element) -> None:
    """At most :data:`MAX_LINKS` links, :data:`MAX_JOINTS` joints, :data:`MAX_TREE_DEPTH` deep."""
    links = root.findall("link")
    joints = root.findall("joint")
    for what, found, bound in (("links", links, MAX_LINKS), ("joints", joints, MAX_JOINTS)):
        if len(found) > bound:
            raise ModelError(
                f"{path}: {len(found)} {what}, more than the {bound} a robot model may have"
            )
    parent_of: dict[str, str] = {}
    for joint in joints:
        parent, child = joint.find("parent"), joint.find("child")
        if parent is not None and child is not None:
            parent_of.setdefault(child.get("link", ""), parent.get("link", ""))
    depth: dict[str, int] = {}
    for link in parent_of:
        chain: list[str] = []
        node = link
        while node in parent_of and node not in depth and len(chain) <= MAX_TREE_DEPTH + 1:
            chain.append(node)
            node = parent_of[node]
        base = depth.get(node, 0)
        for k, name in enumerate(reversed(chain), start=1):
            depth[name] = base + k
        if chain and depth[chain[0]] > MAX_TREE_DEPTH:
            raise ModelError(
                f"{path}: link {chain[0]!r} is more than {MAX_TREE_DEPTH} joints from the root "
                f"(the most a robot model may have), or its joints form a loop"
            )


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
        ModelError: Missing, not a regular file, too large, not UTF-8, not well-formed, with a
            DTD or entities, too many or too deeply nested elements, not a ``<robot>``, too many
            links or joints or too deep a tree, or with a non-finite or unphysical number; the
            message names the file and the element.
    """
    path = Path(path)
    text = read_untrusted_text(path, "URDF", MAX_URDF_BYTES, ModelError)
    root = _parse(path, text.encode("utf-8"))
    if root.tag != "robot":
        raise ModelError(f"{path}: the root element is <{root.tag}>, not <robot>")
    _check_size(path, root)
    _check_links(path, root)
    _check_joints(path, root)
    return text


def read_srdf_text(path: str | Path) -> str:
    """The text of an SRDF file: a regular file, bounded, UTF-8, well-formed, without a DTD.

    Raises:
        ModelError: It is not (the message names the file).
    """
    path = Path(path)
    text = read_untrusted_text(path, "SRDF", MAX_SRDF_BYTES, ModelError)
    root = _parse(path, text.encode("utf-8"), "SRDF")
    if root.tag != "robot":
        raise ModelError(f"{path}: the root element is <{root.tag}>, not <robot>")
    return text


PACKAGE_PREFIX = "package://"


def _mesh_elements(text: str) -> tuple[Element, list[Element]]:
    root = fromstring(text.encode("utf-8"), forbid_dtd=True)
    return root, list(root.iter("mesh"))


def with_resolved_meshes(urdf: Path, text: str, packages: Mapping[str, Path]) -> str:
    """The URDF text with every ``<mesh filename>`` replaced by the absolute path it resolves to.

    Each reference is checked by :func:`resolve_mesh`.

    Raises:
        ModelError: A reference leaves its folder or names no file.
    """
    root, meshes = _mesh_elements(text)
    for mesh in meshes:
        mesh.set("filename", str(resolve_mesh(urdf, mesh.get("filename", ""), packages)))
    return tostring(root, encoding="unicode")


def with_local_meshes(
    urdf: Path,
    text: str,
    packages: Mapping[str, Path],
    folder: Path,
    came_from: Path | None = None,
) -> str:
    """The URDF text with every mesh replaced by a bounded copy in ``folder``.

    Each reference is resolved by :func:`resolve_mesh`, read by
    :func:`~scalf_opt.files.read_untrusted` (a regular file of at most :data:`MAX_MESH_BYTES`,
    :data:`MAX_MESHES_BYTES` for all the robot's meshes together) and copied into ``folder``
    (private, removed by the caller); the mesh loader is given the copies only, so it reads no
    file the checks did not read, however a mesh file refers to others.

    ``came_from`` is the URDF this one was derived from (a variant's parent,
    :func:`resolve_mesh`).

    Raises:
        ModelError: A reference leaves its folder, names no regular file, or a mesh, or all of
            them, are larger than allowed.
    """
    root, meshes = _mesh_elements(text)
    copies: dict[str, Path] = {}
    total = 0
    for mesh in meshes:
        filename = mesh.get("filename", "")
        if filename not in copies:
            source = resolve_mesh(urdf, filename, packages, came_from)
            data = read_untrusted(source, "mesh", MAX_MESH_BYTES, ModelError)
            total += len(data)
            if total > MAX_MESHES_BYTES:
                raise ModelError(
                    f"{urdf}: its meshes are larger than the {MAX_MESHES_BYTES} bytes allowed "
                    f"for one robot (reached at {filename!r})"
                )
            copy = folder / f"mesh{len(copies)}{source.suffix.lower()}"
            copy.write_bytes(data)
            copies[filename] = copy
        mesh.set("filename", str(copies[filename]))
    return tostring(root, encoding="unicode")


_MAX_LINK_HOPS = 40


def _component_info(candidate: Path, urdf: Path, filename: str) -> os.stat_result:
    """``lstat`` of one component of a mesh path (a link is not followed).

    Raises:
        ModelError: It does not exist, or cannot be looked at.
    """
    try:
        return os.lstat(candidate)
    except FileNotFoundError:
        raise ModelError(f"{urdf}: mesh {filename!r}: no such file ({candidate})") from None
    except OSError as exc:
        raise ModelError(f"{urdf}: mesh {filename!r}: {exc.strerror} ({candidate})") from None


def _link_parts(
    link_path: Path, root: Path, current: Path, out: ModelError
) -> tuple[Path, list[str]]:
    """Where a symbolic link's target is walked from, and its components, read as text.

    A relative target is walked from the link's folder ``current``; an absolute one from
    ``root``, when it lies inside it.

    Raises:
        ModelError: ``out``, when an absolute target lies outside ``root``.
    """
    link = os.readlink(link_path)
    if os.path.isabs(link):
        target = Path(os.path.normpath(link))
        if not target.is_relative_to(root):
            raise out
        current = root
        link = str(target.relative_to(root))
    return current, [p for p in link.split(os.sep) if p not in ("", ".")]


def _confined(folder: Path, relative: str, urdf: Path, filename: str, where: str) -> Path:
    """The regular file ``relative`` names inside ``folder``, never looking outside it.

    The path is normalised as text first (``..`` may not climb out); then each component is
    looked at with ``lstat`` from ``folder`` down, and a symbolic link is followed only when
    its target, as text, stays inside ``folder``: no file outside is opened or even stat'ed.

    Raises:
        ModelError: The path leads out, or names no regular file.
    """
    root = folder.resolve()
    out = ModelError(f"{urdf}: mesh {filename!r} leads out of {where} {root}")
    if not relative or posixpath.isabs(relative) or "\0" in relative:
        raise out
    pending = [p for p in relative.split("/") if p not in ("", ".")]
    current = root
    hops = 0
    while pending:
        part = pending.pop(0)
        if part == "..":
            current = current.parent
            if not current.is_relative_to(root):
                raise out
            continue
        candidate = current / part
        info = _component_info(candidate, urdf, filename)
        if stat.S_ISLNK(info.st_mode):
            hops += 1
            if hops > _MAX_LINK_HOPS:
                raise out
            current, followed = _link_parts(candidate, root, current, out)
            pending = followed + pending
            continue
        if pending and not stat.S_ISDIR(info.st_mode):
            raise ModelError(f"{urdf}: mesh {filename!r}: no such file ({candidate})")
        current = candidate
    try:
        info = os.lstat(current)
    except OSError:
        raise ModelError(f"{urdf}: mesh {filename!r}: no such file ({current})") from None
    if not stat.S_ISREG(info.st_mode):
        raise ModelError(f"{urdf}: mesh {filename!r}: not a regular file ({current})")
    return current


def _package_roots(homes: Sequence[Path], package: str, packages: Mapping[str, Path]) -> list[Path]:
    """The folders ``package://package/`` may mean for a URDF whose description is in ``homes``.

    ``homes`` are the URDF's folder and, for a derived URDF (a variant), the folder of the URDF
    it was derived from. A real ROS package among their ancestors (a folder of that name holding
    a ``package.xml``), or the robot description package they lie in (``packages``: a package
    without a ``package.xml``, such as example-robot-data).
    """
    roots: list[Path] = []
    known = packages.get(package)
    for here in homes:
        if known is not None and here.is_relative_to(known.resolve()):
            roots.append(known.resolve())
        for folder in (here, *here.parents):
            if folder.name == package and (folder / "package.xml").is_file():
                roots.append(folder)
    return list(dict.fromkeys(roots))


def resolve_mesh(
    urdf: Path, filename: str, packages: Mapping[str, Path], came_from: Path | None = None
) -> Path:
    """The file a mesh reference names, which must stay inside the robot's description.

    A ``package://NAME/rest`` reference resolves to ``rest`` inside a real package root named
    ``NAME`` (:func:`_package_roots`) and must stay inside it; any other reference is a path
    relative to the URDF's folder and must stay inside it (:func:`_confined`). The empty
    package name (``package:///abs/path``), ``.`` and ``..``, absolute paths and other URI
    schemes are refused: a URDF from the internet must not make scalf-opt read (and embed in a
    page) a file elsewhere on the disk, nor learn whether one exists.

    Args:
        urdf: The URDF.
        filename: The ``<mesh filename>``.
        packages: Robot description packages without a ``package.xml``, by name (the catalog's).
        came_from: The URDF this one was derived from (a variant's parent): its description's
            packages are this one's too.

    Raises:
        ModelError: The reference leaves its folder, or is of another kind.
    """
    here = urdf.resolve().parent
    if filename.startswith(PACKAGE_PREFIX):
        package, _, rest = filename[len(PACKAGE_PREFIX) :].partition("/")
        refused = ModelError(
            f"{urdf}: mesh {filename!r} is not a file inside a package folder {package!r} "
            "above the URDF (a folder of that name with a package.xml) or among the known "
            "robot descriptions"
        )
        if package in ("", ".", "..") or "\\" in package:
            raise refused
        homes = [here] if came_from is None else [here, came_from.resolve().parent]
        roots = _package_roots(homes, package, packages)
        if not roots:
            raise refused
        errors = []
        for root in roots:
            try:
                return _confined(root, rest, urdf, filename, f"package {package!r}")
            except ModelError as exc:
                errors.append(exc)
        raise errors[0]
    if "://" in filename or filename.startswith("/") or Path(filename).is_absolute():
        raise ModelError(
            f"{urdf}: mesh {filename!r}: only paths relative to the URDF's folder and "
            "package:// references are allowed"
        )
    return _confined(here, filename, urdf, filename, "the URDF's folder")
