"""Untrusted URDFs: refused with one line naming the file and element, before Pinocchio."""

import time

import pytest

from scalf_opt.errors import ModelError
from scalf_opt.model import urdf_file
from scalf_opt.robots.files import shipped_file
from scalf_opt.robots.loading import load_robot

SCALF = shipped_file("scalf.urdf").read_text(encoding="utf-8")
THIGH_MASS = '<mass value="4.1"/>'


def write(tmp_path, text, name="robot.urdf"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        (THIGH_MASS, '<mass value="nan"/>', r"link 'RF_thigh' mass = 'nan' is not a finite"),
        (THIGH_MASS, '<mass value="-4.1"/>', r"link 'RF_thigh' mass = -4.1 kg is negative"),
        (THIGH_MASS, '<mass value="heavy"/>', r"mass = 'heavy' is not a number"),
        ('ixx="0.178"', 'ixx="inf"', r"link 'RF_thigh' inertia ixx = 'inf'"),
        ('lower="-2.032"', 'lower="3"', r"joint 'RF_hip_pitch' limit lower = 3 is above upper"),
        ('upper="2.57"', 'upper="nan"', r"joint 'RF_knee' limit upper = 'nan'"),
        ('<robot name="scalf">', "<robut>", "not well-formed XML"),
    ],
)
def test_bad_numbers_are_named(tmp_path, old, new, match):
    assert old in SCALF
    with pytest.raises(ModelError, match=match):
        load_robot(urdf=write(tmp_path, SCALF.replace(old, new, 1)))


def test_an_unphysical_body_inertia_is_refused(tmp_path):
    # Iyy of the thigh far above Ixx + Izz: the triangle inequality fails
    text = SCALF.replace('iyy="0.178"', 'iyy="5.0"', 1)
    with pytest.raises(ModelError, match="triangle inequality"):
        load_robot(urdf=write(tmp_path, text))
    text = SCALF.replace('iyy="0.178"', 'iyy="-0.178"', 1)
    with pytest.raises(ModelError, match="is not positive"):
        load_robot(urdf=write(tmp_path, text))


def test_a_massless_leg_link_and_a_sliding_knee_are_refused(tmp_path):
    with pytest.raises(ModelError, match=r"body of RF_hip_pitch: mass 0\.0 kg is not positive"):
        load_robot(urdf=write(tmp_path, SCALF.replace(THIGH_MASS, '<mass value="0"/>', 1)))
    knee = SCALF.index('<joint name="RF_knee" type="revolute">')
    text = SCALF[:knee] + SCALF[knee:].replace('type="revolute"', 'type="prismatic"', 1)
    # the legs are found in the kinematic tree: a sliding knee is not a leg's joint about y
    with pytest.raises(ModelError, match=r"found 3 legs .* RF_hip_roll -> RF_hip_pitch -> RF_knee"):
        load_robot(urdf=write(tmp_path, text, "sliding.urdf"))


def test_entities_are_refused_and_never_read(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    leak = SCALF.replace(
        '<?xml version="1.0"?>',
        f'<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY s SYSTEM "file://{secret}">]>',
    ).replace('<robot name="scalf">', '<robot name="&s;">')
    with pytest.raises(ModelError, match="document type declarations") as info:
        load_robot(urdf=write(tmp_path, leak))
    assert "TOP-SECRET" not in str(info.value)
    lol = "".join(f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' for i in range(1, 10))
    bomb = f'<?xml version="1.0"?><!DOCTYPE r [<!ENTITY l0 "lol">{lol}]><robot name="&l9;"/>'
    start = time.perf_counter()
    with pytest.raises(ModelError, match="document type declarations"):
        load_robot(urdf=write(tmp_path, bomb, "bomb.urdf"))
    assert time.perf_counter() - start < 5  # refused before any expansion (not a speed test)


def test_non_utf8_and_oversized_files(tmp_path, monkeypatch):
    path = tmp_path / "latin1.urdf"
    path.write_bytes(SCALF.replace("SCalf", "SCalf \xe9").encode("latin-1"))
    with pytest.raises(ModelError, match="not UTF-8"):
        load_robot(urdf=path)
    monkeypatch.setattr(urdf_file, "MAX_URDF_BYTES", 1000)
    with pytest.raises(ModelError, match="larger than the 1000 bytes allowed"):
        load_robot(urdf=write(tmp_path, SCALF))


def test_published_robots_pass():
    # their massless marker links with degenerate inertias vanish in Pinocchio's merged bodies
    for name in ("scalf", "hyq", "solo12"):
        assert load_robot(name).model.nq == 12


MEASURE = """
import resource, subprocess, sys, time
start = time.perf_counter()
done = subprocess.run(sys.argv[1:], capture_output=True, text=True)
seconds = time.perf_counter() - start
peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024  # Linux: kB
print(done.returncode, round(seconds, 2), round(peak_mb), done.stderr.strip(), sep="|")
"""


@pytest.mark.parametrize("kind", ["expansion bomb", "external entity", "oversized"])
def test_hostile_urdfs_are_refused_within_5_s_and_500_mb(tmp_path, kind):
    """The whole command, interpreter start and imports included, on its own: the time and the
    peak memory of that one process (a generous bound on a shared machine, not a speed test)."""
    import subprocess
    import sys

    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET")
    if kind == "expansion bomb":
        lol = "".join(f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' for i in range(1, 12))
        text = f'<?xml version="1.0"?><!DOCTYPE r [<!ENTITY l0 "lol">{lol}]><robot name="&l11;"/>'
    elif kind == "external entity":
        text = SCALF.replace(
            '<?xml version="1.0"?>',
            f'<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY s SYSTEM "file://{secret}">]>',
        ).replace('<robot name="scalf">', '<robot name="&s;">')
    else:  # 30 MB of comments: refused by its size before it is parsed
        text = SCALF.replace("<robot", "<!--" + "x" * 30_000_000 + "-->\n<robot", 1)
    urdf = write(tmp_path, text)
    argv = [sys.executable, "-m", "scalf_opt", "view", "--urdf", str(urdf), "--out", "v.html"]
    done = subprocess.run(
        [sys.executable, "-c", MEASURE, *argv], cwd=tmp_path, capture_output=True, text=True
    )
    code, seconds, peak_mb, stderr = done.stdout.strip().split("|", 3)
    assert code == "2" and stderr.startswith("scalf-opt: error: ") and "\n" not in stderr
    assert str(urdf) in stderr and "TOP-SECRET" not in stderr
    assert float(seconds) < 5 and float(peak_mb) < 500
    assert not (tmp_path / "v.html").exists()
