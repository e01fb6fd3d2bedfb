"""The bad-input corpus (cases.toml): one line, exit code 2, the documented error, nothing written.

A case's command runs twice: through ``scalf-opt`` (``main``), which must print exactly one line
on stderr and return 2 without a traceback, and through the command's own function, which must
raise the case's exception type: what an API caller catches. A hostile case (``isolated``) also
runs as a process of its own with a fresh HOME, TMPDIR and compile cache, under a time and a
memory cap, and must leave no temporary file anywhere.
"""

import hashlib
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from scalf_opt import errors
from scalf_opt.cli import main
from scalf_opt.cli.app import build_parser
from scalf_opt.cli.console import Console
from scalf_opt.robots.files import shipped_file

CORPUS = Path(__file__).with_name("cases.toml")
CASES = tomllib.loads(CORPUS.read_text(encoding="utf-8"))["case"]


def test_the_corpus_is_large_and_covers_every_input():
    ids = [c["id"] for c in CASES]
    assert len(ids) == len(set(ids)) >= 40
    kinds = {i.split("-")[0] for i in ids}
    assert {"urdf", "actuators", "gait", "option", "study", "log", "saved"} <= kinds


def generated(kind: str) -> bytes:
    """A large or deep input, described in one word: ``what:size``."""
    what, _, size = kind.partition(":")
    n = int(size)
    inertial = (
        "<inertial><mass value='1'/><inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0' iyz='0'/>"
        "</inertial>"
    )
    if what == "bytes":
        return b"solid x\n" + b"x" * (n - 8)
    if what in ("chain", "star"):
        links = "".join(f"<link name='l{i}'>{inertial}</link>" for i in range(n))
        joints = "".join(
            f"<joint name='j{i}' type='revolute'><parent link='l{i if what == 'chain' else 0}'/>"
            f"<child link='l{i + 1}'/><axis xyz='0 1 0'/>"
            "<limit lower='-1' upper='1' effort='1' velocity='1'/></joint>"
            for i in range(n - 1)
        )
        return f"<robot name='r'>{links}{joints}</robot>".encode()
    if what == "nested-xml":
        return ("<robot name='r'>" + "<a>" * n + "</a>" * n + "</robot>").encode()
    if what == "nested-json":
        return ("[" * n + "]" * n).encode()
    if what == "toml-digits":  # an integer of n digits in a gait file
        return f"[gait]\nperiod_s = {'1' * n}\n".encode()
    if what == "toml-long-string":  # a gait field of n characters
        return f'[gait]\nperiod_s = "{"x" * n}"\n'.encode()
    if what == "study-cases":  # n x n cases, every one failing the same fixed gait field
        periods = ", ".join(f"{0.4 + 0.001 * k:.3f}" for k in range(n))
        steps = ", ".join(f"{0.2 + 0.0005 * k:.4f}" for k in range(n))
        return (
            '[study]\nrobot = "scalf"\n[gait]\nclearance_m = 0.7\n[sweep]\n'
            f'"gait.period_s" = [{periods}]\n"gait.step_length_m" = [{steps}]\n'
        ).encode()
    if what == "json-digits":  # an integer of n digits in a summary
        return f'{{"gait": {{"period_s": {"1" * n}}}}}'.encode()
    if what == "log-rate":  # RF alone, sampled at n Hz
        rows = "".join(f"{k / n!r},RF,0.3,0.3,100,100\n" for k in range(200))
        return ("t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n\n" + rows).encode()
    if what == "sqlite-view":  # a sqlite3 bag whose messages are a recursive view of n rows
        return _sqlite_bytes(
            "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, "
            "serialization_format TEXT, offered_qos_profiles TEXT);"
            "CREATE TABLE m0(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, "
            "data BLOB);"
            "WITH RECURSIVE k(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM k LIMIT "
            f"{n}) INSERT INTO m0 SELECT i, 1, i, x'00' FROM k;"
            "CREATE VIEW messages AS WITH RECURSIVE r(id, topic_id, timestamp, data) AS "
            "(SELECT * FROM m0 UNION ALL SELECT * FROM r) SELECT * FROM r ORDER BY timestamp;"
        )
    raise AssertionError(f"unknown generated input {kind!r}")


def _sqlite_bytes(script: str) -> bytes:
    """The bytes of a sqlite3 database that ``script`` builds."""
    import sqlite3

    database = sqlite3.connect(":memory:")
    database.executescript(script)
    return database.serialize()


def materialize(case, tmp_path):
    """Write the case's files; return the argv with its placeholders filled."""
    names = {"out": str(tmp_path / "out"), "keep": str(tmp_path / "keep")}
    keep = tmp_path / "keep"
    keep.mkdir()
    (keep / "summary.json").write_text("previous")
    for spec in case.get("files", []):
        path = tmp_path / "in" / spec["name"]
        path.parent.mkdir(parents=True, exist_ok=True)
        if "link" in spec:
            path.symlink_to(spec["link"])
        elif spec.get("fifo"):
            os.mkfifo(path)
        elif "generate" in spec:
            path.write_bytes(generated(spec["generate"]))
        elif "hex" in spec:
            path.write_bytes(bytes.fromhex(spec["hex"]))
        else:
            text = shipped_file(spec["from"]).read_text(encoding="utf-8") if "from" in spec else ""
            text = spec.get("text", text)
            for old, new in spec.get("replace", []):
                assert old in text, f"{case['id']}: {old!r} is not in {spec['from']}"
                text = text.replace(old, new, 1)
            path.write_text(text, encoding="utf-8")
        names[spec["name"]] = str(path)
        if "/" in spec["name"]:  # "opt/summary.json": {opt} is the folder
            names[spec["name"].split("/")[0]] = str(path.parent)
    return [re.sub(r"\{([^}]+)\}", lambda m: names[m.group(1)], arg) for arg in case["argv"]]


def inputs_state(tmp_path):
    """What the input folder holds: each entry's kind and, for regular files, a hash."""
    state = {}
    folder = tmp_path / "in"
    for path in sorted(folder.rglob("*")) if folder.exists() else []:
        if path.is_symlink():
            state[str(path)] = ("link", os.readlink(path))
        elif path.is_file():
            state[str(path)] = ("file", hashlib.sha256(path.read_bytes()).hexdigest())
        else:
            state[str(path)] = ("other", path.stat().st_mode)
    return state


def leftovers(tmp_path):
    """Temporary files, staging folders and locks anywhere under the case's folder."""
    return [
        p
        for p in tmp_path.rglob("*")
        if not p.is_relative_to(tmp_path / "home")
        and (
            re.search(r"\.tmp$|\.stage-|\.lock$|^scalf-opt-", p.name)
            or (p.is_relative_to(tmp_path / "tmp") and p != tmp_path / "tmp")
        )
    ]


CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f]")


def untouched(tmp_path):
    keep = tmp_path / "keep"
    return (
        not (tmp_path / "out").exists()
        and [p.name for p in keep.iterdir()] == ["summary.json"]
        and (keep / "summary.json").read_text() == "previous"
    )


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_bad_input(case, tmp_path, capsys):
    argv = materialize(case, tmp_path)
    before = inputs_state(tmp_path)
    if case["error"] == "usage":
        with pytest.raises(SystemExit) as info:
            main(argv)
        code = info.value.code
    else:
        code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("scalf-opt: error: "), err
    assert "Traceback" not in err and not CONTROL.search(err.rstrip("\n")), err
    assert re.search(case["message"], err), f"{case['message']!r} not in {err!r}"
    assert untouched(tmp_path) and inputs_state(tmp_path) == before
    assert leftovers(tmp_path) == []
    if case["error"] not in ("usage", "cli"):
        args, _ = build_parser().parse_known_args(argv)
        args.console, args.argv = Console(quiet=True), ["scalf-opt", *argv]
        with pytest.raises(getattr(errors, case["error"])):
            args.run(args)
        assert untouched(tmp_path) and inputs_state(tmp_path) == before


ISOLATED = [c for c in CASES if c.get("isolated")]

TIME_CAP_S = 60.0
"""Each isolated case's wall time, interpreter start and imports included (a generous bound on
a shared machine: the cases take 2 to 5 s; not a speed test)."""

MEMORY_CAP_MB = 1024.0
"""Each isolated case's peak resident memory [MB] (the imports alone take ~250 MB)."""

MEASURE = """
import resource, subprocess, sys
timeout_s, cwd, command = float(sys.argv[1]), sys.argv[2], sys.argv[3:]
done = subprocess.run(command, cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True,
                      text=True, timeout=timeout_s)
peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024  # Linux: kB
print(done.returncode, round(peak_mb), sep="|")
sys.stderr.write(done.stderr)
"""


def test_the_isolated_cases_cover_every_class():
    kinds = {c["id"].split("-")[0] for c in ISOLATED}
    assert {"gait", "urdf", "mesh", "srdf", "actuators", "legs", "saved", "log"} <= kinds
    assert {"output", "study"} <= kinds and len(ISOLATED) >= 25


@pytest.mark.parametrize("case", ISOLATED, ids=[c["id"] for c in ISOLATED])
def test_isolated_case(case, tmp_path):
    """The case as a stranger runs it: its own process, fresh HOME, TMPDIR and cache, capped."""
    argv = materialize(case, tmp_path)
    before = inputs_state(tmp_path)
    for name in ("home", "tmp", "cache", "work"):
        (tmp_path / name).mkdir()
    env = {
        **{k: v for k, v in os.environ.items() if not k.startswith(("SCALF_OPT", "XDG_"))},
        "HOME": str(tmp_path / "home"),
        "TMPDIR": str(tmp_path / "tmp"),
        "SCALF_OPT_CACHE": str(tmp_path / "cache"),
        "MPLCONFIGDIR": str(tmp_path / "home" / "mpl"),
    }
    wrapper = [sys.executable, "-c", MEASURE, str(TIME_CAP_S), str(tmp_path / "work")]
    done = subprocess.run(
        [*wrapper, sys.executable, "-m", "scalf_opt", *argv],
        env=env,
        capture_output=True,
        text=True,
        timeout=TIME_CAP_S + 30,
    )
    code, peak_mb = done.stdout.strip().split("|")
    err = done.stderr
    assert code == "2", err
    assert len(err.splitlines()) <= 3 and err.startswith("scalf-opt: error: "), err
    assert "Traceback" not in err and not CONTROL.search(err.rstrip("\n")), err
    assert re.search(case["message"], err), f"{case['message']!r} not in {err!r}"
    assert float(peak_mb) < MEMORY_CAP_MB, f"{peak_mb} MB"
    assert untouched(tmp_path) and inputs_state(tmp_path) == before
    assert leftovers(tmp_path) == [] and not any((tmp_path / "work").iterdir())
