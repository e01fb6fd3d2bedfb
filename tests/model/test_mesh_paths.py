"""Mesh references in an untrusted URDF may not lead out of the robot's description."""

from pathlib import Path

import pytest

from scalf_opt.cli import main
from scalf_opt.errors import ModelError
from scalf_opt.model.urdf_file import resolve_mesh, with_resolved_meshes
from scalf_opt.robots.files import shipped_file
from scalf_opt.viz.visuals import description_packages

SCALF = shipped_file("scalf.urdf").read_text(encoding="utf-8")


@pytest.fixture
def description(tmp_path):
    """robots/demo_description/urdf/demo.urdf with meshes/foot.stl beside urdf/ and a secret."""
    root = tmp_path / "robots" / "demo_description"
    (root / "urdf").mkdir(parents=True)
    (root / "meshes").mkdir()
    (root / "package.xml").write_text("<package><name>demo_description</name></package>")
    (root / "meshes" / "foot.stl").write_text("solid foot\nendsolid foot\n")
    (root / "urdf" / "local.stl").write_text("solid local\nendsolid local\n")
    (tmp_path / "secret.txt").write_text("TOP-SECRET")
    return root / "urdf" / "demo.urdf"


def test_references_inside_the_description_resolve(description):
    meshes = description.parent.parent / "meshes"
    assert (
        resolve_mesh(description, "package://demo_description/meshes/foot.stl", {})
        == (meshes / "foot.stl").resolve()
    )
    assert resolve_mesh(description, "local.stl", {}) == (description.parent / "local.stl")


@pytest.mark.parametrize(
    ("filename", "match"),
    [
        ("../../../secret.txt", "leads out of the URDF's folder"),
        ("../meshes/foot.stl", "leads out of the URDF's folder"),
        ("/etc/passwd", "only paths relative to the URDF's folder"),
        ("file:///etc/passwd", "only paths relative to the URDF's folder"),
        ("package://demo_description/../../secret.txt", "leads out of package .demo_description."),
        ("package://elsewhere/meshes/foot.stl", "not a file inside a package folder"),
        ("missing.stl", "no such file"),
        # the file system's root is the folder of empty name: no package
        ("package:///etc/passwd", "not a file inside a package folder ''"),
        # an ancestor folder matched by its name alone is no package (no package.xml)
        ("package://robots/demo_description/meshes/foot.stl", "not a file inside a package"),
        ("package://../meshes/foot.stl", "not a file inside a package"),
        # a package known by name, but the URDF does not come from it
        ("package://example-robot-data/robots/hyq_description/meshes/x.stl", "not a file inside"),
    ],
)
def test_references_that_escape_are_refused(description, filename, match):
    with pytest.raises(ModelError, match=match):
        resolve_mesh(description, filename, {})


def test_a_symbolic_link_out_is_refused(description):
    link = description.parent / "sneaky.stl"
    link.symlink_to(description.parents[3] / "secret.txt")
    with pytest.raises(ModelError, match="leads out"):
        resolve_mesh(description, "sneaky.stl", {})


def test_the_view_refuses_a_urdf_whose_mesh_escapes(description, tmp_path, capsys):
    text = SCALF.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="../../../secret.txt"/>', 1)
    assert text != SCALF
    description.write_text(text, encoding="utf-8")
    out = tmp_path / "scene.html"
    # the trunk-only loads: view optimizes before it reads the meshes, and on a busy machine a
    # longer optimization prints progress lines before the error
    argv = ["view", "--urdf", str(description), "--loads", "trunk", "--out", str(out)]
    assert main([*argv, "--cycles", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "leads out of the URDF's folder" in err
    assert not out.exists()
    assert "TOP-SECRET" not in with_resolved_meshes(description, SCALF, {})


def test_published_meshes_resolve(hyq):
    text = hyq.urdf_path.read_text(encoding="utf-8")
    resolved = with_resolved_meshes(hyq.urdf_path, text, description_packages())
    assert "package://" not in resolved
    assert all(Path(p).is_file() for p in _filenames(resolved))


def _filenames(text):
    import re

    return re.findall(r'<mesh filename="([^"]+)"', text)


def test_nothing_outside_is_looked_at(description, monkeypatch):
    """Every path lstat'ed while resolving lies inside the URDF's folder (or leads to it)."""
    import os

    seen = []
    real = os.lstat
    monkeypatch.setattr(os, "lstat", lambda p, *a, **k: seen.append(Path(p)) or real(p, *a, **k))
    outside = description.parents[3] / "secret.txt"
    (description.parent / "hop").symlink_to("../../../secret.txt")
    (description.parent / "absolute").symlink_to(outside)
    for name in ("hop", "absolute", "../../../secret.txt", "../../../nothing/here.stl"):
        with pytest.raises(ModelError, match="leads out"):
            resolve_mesh(description, name, {})
    inside = description.parent.resolve()
    # the URDF's own path is resolved (its ancestors); nothing else outside its folder is seen
    assert seen and all(p.is_relative_to(inside) or inside.is_relative_to(p) for p in seen)
    assert not any(p.name in ("secret.txt", "nothing") for p in seen)


def test_a_link_that_stays_inside_is_followed(description):
    (description.parent / "alias.stl").symlink_to("local.stl")
    assert resolve_mesh(description, "alias.stl", {}) == description.parent / "local.stl"


def test_oversized_and_special_meshes_are_refused(description, tmp_path, monkeypatch):
    from scalf_opt.model import urdf_file
    from scalf_opt.model.urdf_file import with_local_meshes

    (description.parent / "zero.stl").symlink_to("/dev/zero")
    text = SCALF.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="zero.stl"/>', 1)
    with pytest.raises(ModelError, match="leads out"):
        with_local_meshes(description, text, {}, tmp_path)
    (description.parent / "big.stl").write_bytes(b"x" * 3000)
    monkeypatch.setattr(urdf_file, "MAX_MESH_BYTES", 2000)
    text = SCALF.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="big.stl"/>', 1)
    with pytest.raises(ModelError, match=r"big\.stl: mesh file is larger than the 2000 bytes"):
        with_local_meshes(description, text, {}, tmp_path)
    monkeypatch.setattr(urdf_file, "MAX_MESH_BYTES", 4000)
    monkeypatch.setattr(urdf_file, "MAX_MESHES_BYTES", 5000)
    text = SCALF.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="big.stl"/>', 1)
    text = text.replace('<mesh filename="big.stl"/>', '<mesh filename="big.stl"/>', 1)
    twice = text.replace(
        "</robot>",
        '<link name="x"><visual><geometry><mesh filename="local.stl"/>'
        "</geometry></visual></link></robot>",
    )
    (description.parent / "local.stl").write_bytes(b"y" * 2500)
    with pytest.raises(ModelError, match="meshes are larger than the 5000 bytes allowed"):
        with_local_meshes(description, twice, {}, tmp_path)
