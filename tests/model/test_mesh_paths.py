"""Mesh references in an untrusted URDF may not lead out of the robot's description."""

from pathlib import Path

import pytest

from scalf_opt.cli import main
from scalf_opt.errors import ModelError
from scalf_opt.model.urdf_file import resolve_mesh, with_resolved_meshes
from scalf_opt.robots.files import shipped_file

SCALF = shipped_file("scalf.urdf").read_text(encoding="utf-8")


@pytest.fixture
def description(tmp_path):
    """robots/demo_description/urdf/demo.urdf with meshes/foot.stl beside urdf/ and a secret."""
    root = tmp_path / "robots" / "demo_description"
    (root / "urdf").mkdir(parents=True)
    (root / "meshes").mkdir()
    (root / "meshes" / "foot.stl").write_text("solid foot\nendsolid foot\n")
    (root / "urdf" / "local.stl").write_text("solid local\nendsolid local\n")
    (tmp_path / "secret.txt").write_text("TOP-SECRET")
    return root / "urdf" / "demo.urdf"


def test_references_inside_the_description_resolve(description):
    meshes = description.parent.parent / "meshes"
    assert (
        resolve_mesh(description, "package://demo_description/meshes/foot.stl", [])
        == (meshes / "foot.stl").resolve()
    )
    assert resolve_mesh(description, "local.stl", []) == (description.parent / "local.stl")


@pytest.mark.parametrize(
    ("filename", "match"),
    [
        ("../../../secret.txt", "leads out of the URDF's folder"),
        ("../meshes/foot.stl", "leads out of the URDF's folder"),
        ("/etc/passwd", "only paths relative to the URDF's folder"),
        ("file:///etc/passwd", "only paths relative to the URDF's folder"),
        ("package://demo_description/../../secret.txt", "not a file inside a package folder"),
        ("package://elsewhere/meshes/foot.stl", "not a file inside a package folder"),
        ("missing.stl", "no such file"),
    ],
)
def test_references_that_escape_are_refused(description, filename, match):
    with pytest.raises(ModelError, match=match):
        resolve_mesh(description, filename, [])


def test_a_symbolic_link_out_is_refused(description):
    link = description.parent / "sneaky.stl"
    link.symlink_to(description.parents[3] / "secret.txt")
    with pytest.raises(ModelError, match="leads out"):
        resolve_mesh(description, "sneaky.stl", [])


def test_the_view_refuses_a_urdf_whose_mesh_escapes(description, tmp_path, capsys):
    text = SCALF.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="../../../secret.txt"/>', 1)
    assert text != SCALF
    description.write_text(text, encoding="utf-8")
    out = tmp_path / "scene.html"
    assert main(["view", "--urdf", str(description), "--out", str(out), "--cycles", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "leads out of the URDF's folder" in err
    assert not out.exists()
    assert "TOP-SECRET" not in with_resolved_meshes(description, SCALF, [])


def test_published_meshes_resolve(hyq):
    text = hyq.urdf_path.read_text(encoding="utf-8")
    resolved = with_resolved_meshes(hyq.urdf_path, text, [hyq.urdf_path.parents[2]])
    assert "package://" not in resolved
    assert all(Path(p).is_file() for p in _filenames(resolved))


def _filenames(text):
    import re

    return re.findall(r'<mesh filename="([^"]+)"', text)
