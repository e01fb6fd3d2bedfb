"""The command line fits robotics users' habits: pipes, JSON, quiet, options over files, one-line
errors with the option named, self-describing results, and the API giving the same numbers."""

import hashlib
import json
import subprocess
import sys

import pytest

import scalf_opt
from scalf_opt.cli import main
from scalf_opt.cli.commands import evaluate as evaluate_command
from scalf_opt.io.results import split_timings, to_json
from scalf_opt.types import LEG_NAMES


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def scalf_opt_process(*args, **kwargs):
    return subprocess.run(
        [sys.executable, "-m", "scalf_opt", *args], capture_output=True, text=True, **kwargs
    )


def test_a_closed_pipe_is_not_an_error():
    # `scalf-opt model | head -1`: the reader goes away after one line
    proc = subprocess.Popen(
        [sys.executable, "-m", "scalf_opt", "model"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.readline()
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait() == 0
    assert err == ""


def test_paper_in_a_closed_pipe_still_writes_every_file(tmp_path):
    script = (
        f"{sys.executable} -m scalf_opt paper --quick --rate 100 --out {tmp_path} | head -1; "
        "echo status ${PIPESTATUS[0]}"
    )
    proc = subprocess.run(["bash", "-c", script], capture_output=True, text=True, check=True)
    assert proc.stdout.splitlines()[-1] == "status 0" and "Traceback" not in proc.stderr
    for name in ("report.md", "paper.json", "table5.csv", "table6.csv", "pattern_search.png"):
        assert (tmp_path / name).is_file()


def test_output_paths_are_checked_before_any_work(tmp_path, capsys):
    taken = tmp_path / "a file"
    taken.write_text("keep me")
    code, out, err = run(["paper", "--out", str(taken)], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--out" in err and "is a file" in err
    assert taken.read_text() == "keep me"


def test_json_quiet_and_version(tmp_path, capsys):
    code, out, _ = run(["evaluate", "--json", "--out", str(tmp_path)], capsys)
    assert code == 0
    printed = json.loads(out)
    written = json.loads((tmp_path / "summary.json").read_text())
    assert printed == written
    assert list(printed["legs"]) == list(LEG_NAMES)  # the one leg order, as in samples.csv
    code, out, err = run(["evaluate", "--quiet"], capsys)
    assert code == 0 and out == "" and err == ""
    with pytest.raises(SystemExit) as info:
        main(["--version"])
    assert info.value.code == 0 and capsys.readouterr().out.strip() == (
        f"scalf-opt {scalf_opt.__version__}"
    )
    code, out, _ = run(["model", "--json", "--robot", "hyq"], capsys)
    model = json.loads(out)
    assert model["robot"] == "hyq" and model["joints"][0]["drive"]["kind"] == "valve_cylinder"


def test_result_files_describe_themselves(tmp_path, capsys):
    argv = ["evaluate", "--period", "0.6", "--out", str(tmp_path)]
    assert run(argv, capsys)[0] == 0
    data = json.loads((tmp_path / "summary.json").read_text())
    source = data["provenance"]
    assert source["tool"] == "scalf-opt" and source["version"] == scalf_opt.__version__
    assert source["robot"] == "scalf"
    urdf = scalf_opt.load_robot("scalf").urdf_path
    assert source["urdf"] == str(urdf)
    assert source["urdf_sha256"] == hashlib.sha256(urdf.read_bytes()).hexdigest()
    assert source["command"] == "scalf-opt " + " ".join(argv)
    assert data["gait"]["period_s"] == 0.6


def test_gait_options_override_the_file_and_name_themselves(tmp_path, capsys):
    gait = tmp_path / "gait.toml"
    gait.write_text("[gait]\nperiod_s = 0.6\nstep_length_m = 0.3\n")
    code, out, _ = run(["evaluate", "--json", "--gait", str(gait), "--period", "0.4"], capsys)
    assert code == 0
    fields = json.loads(out)["gait"]
    assert (fields["period_s"], fields["step_length_m"]) == (0.4, 0.3)
    code, _, err = run(["evaluate", "--gait", str(gait), "--rate", "0"], capsys)
    assert code == 2 and err.startswith("scalf-opt: error: --rate 0:") and err.count("\n") == 1
    gait.write_text("[gait]\nduty_cycle = 0.2\n")
    code, _, err = run(["evaluate", "--gait", str(gait)], capsys)
    assert code == 2 and "gait.toml" in err and "duty_cycle" in err


def test_legs_in_any_case_and_options_that_do_not_apply(capsys):
    code, out, _ = run(
        ["optimize", "--leg", "rf", "--family", "paper", "--method", "pattern"], capsys
    )
    assert code == 0 and "RF: paper by pattern: solved" in out and "LH:" not in out
    code, _, err = run(["optimize", "--precision", "0.01"], capsys)
    assert code == 2 and err.startswith("scalf-opt: error: --precision:")
    code, _, err = run(["optimize", "--family", "joint6"], capsys)
    assert code == 2 and err.startswith("scalf-opt: error: --family:")


def test_an_unexpected_failure_is_one_line_with_a_hint(monkeypatch, capsys):
    def broken(args):
        raise RuntimeError("boom")

    monkeypatch.setattr(evaluate_command, "run", broken)
    code, out, err = run(["evaluate"], capsys)
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "RuntimeError: boom" in err and "--debug" in err
    with pytest.raises(RuntimeError, match="boom"):
        main(["evaluate", "--debug"])


def test_paper_on_another_robot_does_not_borrow_scalf_s_story(tmp_path, capsys):
    argv = ["paper", "--robot", "hyq", "--quick", "--rate", "100", "--out", str(tmp_path)]
    code, _, _ = run(argv, capsys)
    report = (tmp_path / "report.md").read_text()
    assert code == 0
    assert report.startswith("# The paper's comparison (Tables 5 and 6) on hyq")
    for scalf_only in ("SCalf paper", "671.52", "-33.76", "z0 (0.75"):
        assert scalf_only not in report
    # its valve-controlled cylinders meter their own power: the accounting's |tau qd| is not it
    assert "power drawn by the drives: supply pressure x flow of the valve-controlled" in report
    assert "|tau qd|` plus the drives' losses" not in report
    history = json.loads((tmp_path / "paper.json").read_text())["optima"]["pattern"]["RF"][
        "history"
    ]
    assert set(history[-1]) == {"iteration", "parameters", "swing_energy_j"}
    assert set(history[-1]["parameters"]) == {"hip_cos3", "knee_cos2"}


def test_the_api_gives_the_command_line_s_numbers(tmp_path, capsys):
    robot = scalf_opt.load_robot("scalf")
    gait = scalf_opt.read_gait(robot=robot, period_s=0.45)
    api = scalf_opt.optimize_swing(robot, gait, family="paper").to_dict()
    code, out, _ = run(["optimize", "--family", "paper", "--period", "0.45", "--json"], capsys)
    cli = json.loads(out)
    assert code == 0
    api.pop("provenance"), cli.pop("provenance")
    assert "wall_time_s" in api["optimization_run"]  # the API keeps the run times ...
    assert json.loads(to_json(split_timings(api)[0])) == cli  # ... --json leaves them out


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["evalute"], "invalid choice: 'evalute'"),
        (["evaluate", "--robot", "hyqq"], "did you mean 'hyq'?"),
        (["evaluate", "--perid", "0.4"], "did you mean '--period'?"),
        # a flag is compared without its dashes: '--method' is no near miss of '--period'
        (["view", "--method", "pattern"], "unrecognized arguments: --method pattern (see"),
        # about as close to two flags: both named, the closer first
        (
            ["variant", "--shank-scale", "1.1", "--out", "v.urdf"],
            "did you mean '--shank-mass-scale' or '--shank-length-scale'?",
        ),
        (["evaluate", "--period", "x"], "argument --period: invalid float value: 'x'"),
        # argparse would keep the last value silently: LH alone, for a user who asked for two
        (["optimize", "--leg", "RF", "--leg", "LH"], "argument --leg: given more than once"),
        (["evaluate", "--robot", "a1", "--robot=go1"], "argument --robot: given more than once"),
        (["evaluate", "--rate", "100", "--ra", "200"], "argument --rate: given more than once"),
    ],
)
def test_a_typo_is_one_line_with_a_suggestion(argv, expected, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1
    assert err.startswith("scalf-opt: error: ") and expected in err and "--help" in err


def test_the_package_offers_exactly_the_api_lazily():
    """``scalf_opt`` repeats the API's names (so that ``import scalf_opt`` loads nothing heavy):
    the two lists must stay the same, and every name must resolve to the API's object."""
    import scalf_opt.api

    assert scalf_opt.__all__ == ["__version__", *scalf_opt.api.__all__]
    for name in scalf_opt.api.__all__:
        assert getattr(scalf_opt, name) is getattr(scalf_opt.api, name)


def test_a_near_miss_of_the_free_bound_is_named_and_nothing_is_written(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["optimize", "--family", "fre", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("scalf-opt: error: --family: unknown family")
    assert err.rstrip().endswith("did you mean 'free'?")
    assert not out.exists()
    assert main(["optimize", "--family", "joint-66"]) == 2  # not near 'free': no suggestion
    assert "did you mean" not in capsys.readouterr().err


@pytest.mark.parametrize(
    ("argv", "module", "extra"),
    [(["simulate", "--cycles", "1"], "mujoco", "sim"), (["view"], "meshcat", "viz")],
)
def test_a_missing_optional_part_is_named_with_its_extra(
    argv, module, extra, tmp_path, capsys, monkeypatch
):
    """Without MuJoCo or meshcat installed, the command says which extra to install (exit 2)."""
    for name in list(sys.modules):  # as if never installed: importing it fails
        if name == module or name.startswith(module + "."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, module, None)
    for name in list(sys.modules):  # the package's modules that import it load again
        if name.startswith(("scalf_opt.sim", "scalf_opt.viz")):
            monkeypatch.delitem(sys.modules, name)
    code, _, err = run([*argv, "--out", str(tmp_path / "out")], capsys)
    assert code == 2, err
    assert err.strip().splitlines() == [
        f"scalf-opt: error: {module} is not installed: scalf-opt {argv[0]} needs the optional "
        f"'{extra}' part (make install in a clone of scalf-opt, which installs every part at "
        f"the pinned versions; else pip install 'scalf-opt[{extra}]')"
    ]
    assert not (tmp_path / "out").exists()
