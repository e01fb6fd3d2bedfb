"""The offline HTML view: self-contained, rendered by a headless Chromium, and from the CLI.

The end-to-end test opens the page in Chromium (offline: no host name resolves) and compares its
screenshot with the same page holding an empty scene (same viewer, background, camera and legend;
no ground, robots or paths): the scene must change at least MIN_CHANGED_SHARE of the pixels, and
the console must show no JavaScript error. Where Chromium is not installed the test is skipped,
and says so (``.ci/run`` installs it).
"""

import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import umsgpack
from matplotlib import image

from scalf_opt.api.presentation import view
from scalf_opt.cli import main
from scalf_opt.files import write_atomic
from scalf_opt.viz.browser import find_chromium, render_page
from scalf_opt.viz.html import scene_page, viewer_script
from scalf_opt.viz.scene import SceneOptions, build_scene
from tests.viz.conftest import COARSE_RATE_HZ

MIN_CHANGED_SHARE = 0.10
"""Share of pixels the scene must change against an empty scene (measured: 0.55 for SCalf's two
robots walking one cycle at 800 x 450 px; the ground alone covers more than this)."""

PIXEL_TOLERANCE = 8 / 255
"""A pixel counts as changed when a channel differs by more than this (anti-aliasing noise)."""

needs_chromium = pytest.mark.skipif(
    find_chromium() is None,
    reason="Chromium is not installed: the end-to-end view test needs it "
    "(apt-get install chromium; .ci/run installs it)",
)
one_chromium_at_a_time = pytest.mark.xdist_group("chromium")
"""The Chromium tests run on one worker (`make test` distributes by group): two headless
Chromiums side by side now and then hang."""


def live_processes_in_group(group):
    """Processes of a process group that still run (zombies awaiting their reaper excluded)."""
    alive = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        state, pgrp = fields[0], int(fields[2])
        if pgrp == group and state != "Z":
            alive.append(stat.parent.name)
    return alive


def children_of_this_process():
    me = os.getpid()
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == me and fields[0] != "Z":
            try:
                command = (stat.parent / "cmdline").read_bytes()
            except OSError:
                continue
            # Python's own multiprocessing resource tracker (started once per interpreter by
            # any process pool, e.g. an earlier study test's) lives as long as the interpreter
            if b"multiprocessing.resource_tracker" not in command:
                found.append(stat.parent.name)
    return found


@pytest.fixture(scope="module")
def gait_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("gait") / "coarse.toml"
    path.write_text(f"[gait]\nsample_rate_hz = {COARSE_RATE_HZ}\n")
    return path


@pytest.fixture(scope="module")
def saved_dir(tmp_path_factory, gait_file):
    out = tmp_path_factory.mktemp("optimum")
    code = main(["optimize", "--family", "paper", "--gait", str(gait_file), "--out", str(out)])
    assert code == 0
    return out


def test_page_is_self_contained(scalf, scalf_shown):
    _, shown = scalf_shown
    page = scene_page(build_scene(scalf, shown, SceneOptions(n_cycles=1, frame_rate_hz=10.0)))
    script = viewer_script()
    assert script in page  # meshcat's viewer inline, not loaded
    skeleton = page.replace(script, "")
    for reference in ("src=", "href=", "http:", "https:", "//cdn", "import("):
        assert reference not in skeleton


@needs_chromium
@one_chromium_at_a_time
def test_view_renders_in_headless_chromium(tmp_path, scalf, scalf_shown):
    _, shown = scalf_shown
    scene = build_scene(scalf, shown, SceneOptions(n_cycles=1, frame_rate_hz=20.0))
    kept = ("set_property", "set_transform")
    empty = replace(
        scene, commands=[c for c in scene.commands if umsgpack.unpackb(c)["type"] in kept]
    )
    pictures = {}
    for name, which in (("scene", scene), ("empty", empty)):
        page = write_atomic(tmp_path / f"{name}.html", scene_page(which))
        rendering = render_page(page, tmp_path / f"{name}.png", (800, 450), fragment="t=0.2")
        assert rendering.errors == [], rendering.errors
        assert live_processes_in_group(rendering.process_group) == []
        pictures[name] = image.imread(rendering.screenshot)[:, :, :3]
    changed = np.any(np.abs(pictures["scene"] - pictures["empty"]) > PIXEL_TOLERANCE, axis=2)
    assert changed.mean() > MIN_CHANGED_SHARE, changed.mean()


@needs_chromium
@one_chromium_at_a_time
def test_page_errors_are_caught(tmp_path):
    page = tmp_path / "broken.html"
    page.write_text("<html><head></head><body><script>console.error('bad'); nope();</script>")
    rendering = render_page(page, tmp_path / "broken.png", (200, 100), timeout_s=30)
    assert len(rendering.errors) == 2 and rendering.errors[1].startswith("Uncaught")


def test_view_api_writes_the_page_and_starts_no_process(tmp_path, saved_dir):
    out, shown = view(tmp_path / "api.html", from_dirs=[saved_dir])
    assert [t.label for t in shown] == [
        "reference (cubic spline)",
        f"{saved_dir.name} (paper, ipopt)",
    ]
    text = out.read_text()
    assert text.startswith("<!DOCTYPE html>") and "paper, ipopt" in text
    assert children_of_this_process() == []  # no meshcat server, nothing left running


def test_two_exports_run_at_the_same_time(tmp_path, saved_dir):
    outs = [tmp_path / f"scene{i}.html" for i in range(2)]
    command = [sys.executable, "-m", "scalf_opt", "view", "--from", str(saved_dir), "--cycles", "1"]
    processes = [
        subprocess.Popen(
            [*command, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE
        )
        for out in outs
    ]
    for process in processes:
        _, err = process.communicate(timeout=300)
        assert process.returncode == 0, err
    assert outs[0].read_bytes() == outs[1].read_bytes()  # deterministic, and neither disturbed
    assert not list(tmp_path.glob(".*.tmp"))  # atomic writes leave no temporary file


def test_cli_view_default_and_bad_input(tmp_path, gait_file, saved_dir, capsys):
    out = tmp_path / "default.html"
    code = main(["view", "--gait", str(gait_file), "--cycles", "1", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == 0 and out.is_file()
    assert "reference (cubic spline)" in printed and "optimum (joint-6, ipopt)" in printed
    bad_json = tmp_path / "bad"
    bad_json.mkdir()
    (bad_json / "summary.json").write_text("{not json")
    no_legs = tmp_path / "nolegs"
    no_legs.mkdir()
    summary = json.loads((saved_dir / "summary.json").read_text())
    summary["legs"]["RF"]["swing_parameters"] = [1.0]
    (no_legs / "summary.json").write_text(json.dumps(summary))
    cases = [
        (["--out", str(tmp_path)], "is a directory"),
        (["--out", str(tmp_path / "x.txt")], "must end in .html"),
        (["--from", str(tmp_path / "missing")], "summary.json: not found"),
        (["--from", str(bad_json)], "not valid JSON"),
        (["--from", str(no_legs)], "legs.RF.swing_parameters must be 2 finite numbers"),
        (["--from", str(saved_dir), "--gait", str(gait_file)], "brings its own gait"),
        (["--from", str(saved_dir), "--cycles", "0"], "cycles must be in 1..50"),
    ]
    for argv, message in cases:
        code = main(["view", *argv])
        err = capsys.readouterr().err
        assert code == 2, argv
        assert message in err and len(err.strip().splitlines()) == 1, err


def test_screenshot_without_chromium_fails_before_any_work(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("SCALF_OPT_CHROMIUM", "no-such-browser")
    out = tmp_path / "scene.html"
    code = main(["view", "--out", str(out), "--screenshot", str(tmp_path / "shot.png")])
    err = capsys.readouterr().err
    assert code == 2 and "--screenshot needs Chromium" in err and not out.exists()


def test_view_refuses_a_bad_mesh_before_it_optimizes(tmp_path, monkeypatch, capsys):
    """The meshes are checked up front (as docs/limits.md says): no solve runs first."""
    import scalf_opt.api.presentation as presentation

    def solve(*args, **kwargs):
        raise AssertionError("view optimized before it checked the meshes")

    monkeypatch.setattr(presentation, "shown_trajectories", solve)
    urdf = tmp_path / "robot.urdf"
    text = (Path(__file__).parents[2] / "urdf" / "scalf.urdf").read_text()
    urdf.write_text(text.replace('<box size="1.5 0.45 0.3"/>', '<mesh filename="gone.stl"/>'))
    code = main(["view", "--urdf", str(urdf), "--out", str(tmp_path / "scene.html")])
    assert code == 2
    assert "gone.stl" in capsys.readouterr().err


def test_a_variant_walks_beside_its_parent(tmp_path, capsys):
    """``view --beside-parent``: the variant's reference and optimum, then its parent's on the
    same gait, each label naming its robot; a robot that is no variant is refused first."""
    urdf = tmp_path / "long.urdf"
    assert main(["variant", "--thigh-length-scale", "1.1", "--out", str(urdf), "-q"]) == 0
    argv = ["view", "--urdf", str(urdf), "--beside-parent", "--loads", "trunk"]
    assert main([*argv, "--out", str(tmp_path / "scene.html")]) == 0
    labels = [line.split(":")[0].strip() for line in capsys.readouterr().out.splitlines()[1:5]]
    assert labels == ["long", "long", "scalf", "scalf"]
    page = (tmp_path / "scene.html").read_text()
    assert "long beside scalf" in page and page.count("optimum (joint-6, ipopt)") >= 2
    assert main(["view", "--beside-parent", "--out", str(tmp_path / "no.html")]) == 2
    assert "is not a variant" in capsys.readouterr().err and not (tmp_path / "no.html").exists()
