"""The same commands twice, in two fresh processes, write byte-identical result files.

Run times are the one thing a run cannot repeat: they go to ``timings.json`` beside the result
file, and nowhere else (not in ``summary.json``, ``paper.json``, ``table5.csv``, ``report.md``).

The two runs (five commands, ``paper --quick`` among them, twice) take minutes: their tests are
marked ``slow`` (``make test-all`` and CI run them, ``make test`` does not).
"""

import json
import subprocess
import sys
import textwrap

import pytest

from scalf_opt.io.results import TIMINGS_FILE, is_timing_key, split_timings

STUDY = """\
[study]
robot = "scalf"
family = "paper"

[sweep]
"gait.period_s" = [0.45, 0.5]
"""

COMMANDS = [
    ["evaluate", "--out", "evaluate"],
    ["optimize", "--family", "paper", "--out", "optimize"],
    ["paper", "--quick", "--out", "paper"],
    ["figures", "--from", "optimize", "--grid", "5", "--format", "png", "--out", "figures"],
    ["study", "sweep.toml", "--workers", "1", "--out", "study"],
]

DRIVER = textwrap.dedent(
    """
    import json, sys
    from scalf_opt.cli.app import main
    for argv in json.loads(sys.argv[1]):
        code = main([*argv, "--quiet"])
        if code != 0:
            sys.exit(f"{argv}: exit code {code}")
    """
)


def _run_all(folder):
    folder.mkdir()
    (folder / "sweep.toml").write_text(STUDY)
    done = subprocess.run(
        [sys.executable, "-c", DRIVER, json.dumps(COMMANDS)],
        cwd=folder,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    return {p.relative_to(folder): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("twice")
    return _run_all(root / "first"), _run_all(root / "second")


@pytest.mark.slow
def test_the_same_commands_write_the_same_bytes(two_runs):
    first, second = two_runs
    assert first.keys() == second.keys()
    results = [p for p in first if p.name != TIMINGS_FILE]
    for tool in ("evaluate", "optimize", "paper", "figures", "study"):  # each command wrote some
        assert any(p.parts[0] == tool for p in results), tool
    assert any(p.suffix == ".png" for p in results) and any(p.suffix == ".json" for p in results)
    differing = [str(p) for p in results if first[p] != second[p]]
    assert differing == []


@pytest.mark.slow
def test_run_times_are_only_in_the_timings_files(two_runs):
    first, _ = two_runs
    timings = {p: json.loads(b) for p, b in first.items() if p.name == TIMINGS_FILE}
    assert {str(p.parent) for p in timings} == {"optimize", "paper"}
    assert "wall_time_s" in timings[next(p for p in timings if p.parts[0] == "paper")]["paper.json"]
    for path, data in first.items():
        if path.suffix == ".json" and path.name != TIMINGS_FILE:
            assert split_timings(json.loads(data))[1] == {}, path
        if path.suffix in (".csv", ".md"):
            text = data.decode()
            assert "wall_time" not in text and "Run time" not in text, path


def test_timings_are_split_at_their_paths():
    data = {
        "a": 1,
        "wall_time_s": 2.0,
        "runs": [{"x": 1}, {"x": 2, "solver_stats": {"t_wall_nlp_f": 0.1, "iter_count": 7}}],
    }
    results, timings = split_timings(data)
    assert results == {"a": 1, "runs": [{"x": 1}, {"x": 2, "solver_stats": {"iter_count": 7}}]}
    assert timings == {"wall_time_s": 2.0, "runs": {"1": {"solver_stats": {"t_wall_nlp_f": 0.1}}}}
    assert is_timing_key("solver_time_s") and not is_timing_key("period_s")
