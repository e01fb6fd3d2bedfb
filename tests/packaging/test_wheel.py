"""The wheel works from any folder: it carries SCalf's URDF and sidecar, and lists every package.

The wheel is built offline (no build isolation) and installed, without dependencies, into a fresh
virtual environment that borrows this environment's third-party packages through a ``.pth``
line; the command then runs from a temporary folder, far from the repository.
"""

import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_every_package_is_listed_in_pyproject():
    listed = set(
        tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    )
    found = {
        ".".join(p.parent.relative_to(ROOT).parts)
        for p in (ROOT / "scalf_opt").rglob("__init__.py")
    }
    assert listed == found | {"scalf_opt.urdf"}


def test_installed_wheel_runs_from_another_folder(tmp_path):
    dist = tmp_path / "dist"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            str(ROOT),
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(dist),
        ],
        check=True,
    )
    (wheel,) = dist.glob("scalf_opt-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "scalf_opt/urdf/scalf.urdf" in names and "scalf_opt/urdf/scalf_actuators.toml" in names
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "--python",
            str(python),
            "install",
            "--no-deps",
            "-q",
            str(wheel),
        ],
        check=True,
    )
    site = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    # third-party packages from this environment, after the wheel's own site-packages; as site
    # directories, so that their own .pth files run (Pinocchio's wheel needs its cmeel.pth)
    borrowed = {sysconfig.get_paths()["purelib"], sysconfig.get_paths()["platlib"]}
    lines = [f"import site; site.addsitedir({path!r})" for path in sorted(borrowed)]
    Path(site, "borrowed.pth").write_text("\n".join(lines) + "\n")
    work = tmp_path / "elsewhere"
    work.mkdir()
    run = subprocess.run(
        [str(venv / "bin" / "scalf-opt"), "evaluate"],
        cwd=work,
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    assert "reference swing trajectory on scalf" in run.stdout
    where = subprocess.run(
        [str(python), "-c", "import scalf_opt.robots.files as f; print(f.robot_files_dir())"],
        cwd=work,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    assert where.startswith(site), f"the robot files came from {where}, not from the wheel"
