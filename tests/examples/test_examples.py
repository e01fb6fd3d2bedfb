"""The examples run as a newcomer would run them: the API walk-through script, the notebook (every
cell executed in a fresh kernel), and the input files, each through the command that reads it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from scalf_opt.cli import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
TROTTER = EXAMPLES / "trotter"


@pytest.mark.slow  # every step of the API on a new robot: about 40 s alone
def test_the_walkthrough_script_runs_end_to_end(tmp_path):
    pytest.importorskip("meshcat")
    proc = subprocess.run(
        [sys.executable, str(EXAMPLES / "walkthrough.py"), str(tmp_path)],
        capture_output=True,
        text=True,
        env={"MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"},
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[0].startswith("robot trotter: 25.20 kg")
    assert len(lines) == 9
    assert (tmp_path / "optimum" / "summary.json").is_file()
    assert (tmp_path / "scene.html").is_file()
    assert (tmp_path / "long.urdf").is_file()


@pytest.mark.slow  # every cell in a fresh kernel: about 20 s alone
def test_the_notebook_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("TMPDIR", str(tmp_path))  # the notebook's own folder is left with the test's
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("meshcat")
    notebook = nbformat.read(EXAMPLES / "notebook.ipynb", as_version=4)
    assert all(not cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code")
    client = nbclient.NotebookClient(
        notebook, timeout=300, kernel_name="python3", resources={"metadata": {"path": tmp_path}}
    )
    client.execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    # no warning (the BLAS one, when matplotlib came first), nothing on stderr
    assert not [o for o in outputs if o.output_type == "stream" and o.name == "stderr"]
    kinds = {key for o in outputs for key in o.get("data", {})}
    assert "image/png" in kinds  # the plot
    html = [o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {})]
    assert html and 'src="notebook-view/scene.html"' in html[0]  # the view, in a frame
    page = tmp_path / "notebook-view" / "scene.html"
    assert "three" in page.read_text().lower()
    executed = tmp_path / "executed.ipynb"
    nbformat.write(notebook, executed)
    assert executed.stat().st_size < 1_000_000  # the page stays a file, not the notebook's


def test_the_legs_and_actuator_files_are_the_ones_used(capsys):
    assert main(["model", "--urdf", str(TROTTER / "trotter.urdf"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    text = json.dumps(data)
    assert "front_right_flexion" in text and "electric" in text


def test_the_gait_file_is_read(capsys):
    argv = ["evaluate", "--urdf", str(TROTTER / "trotter.urdf"), "--gait"]
    assert main([*argv, str(TROTTER / "slow_trot.toml"), "--json"]) == 0
    gait = json.loads(capsys.readouterr().out)["gait"]
    assert gait["period_s"] == 0.5 and gait["duty_cycle"] == 0.6 and gait["clearance_m"] == 0.06


@pytest.mark.slow  # six optimizations: about 20 s alone
def test_the_study_file_runs(tmp_path, capsys):
    code = main(
        ["study", str(TROTTER / "speed_study.toml"), "--workers", "1", "--out", str(tmp_path)]
    )
    assert code == 0, capsys.readouterr().err
    rows = (tmp_path / "results.csv").read_text().splitlines()
    assert len(rows) == 1 + 6 and all(",ok," in row for row in rows[1:])
