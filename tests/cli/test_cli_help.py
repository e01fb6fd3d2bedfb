"""One set of habits for every command, checked on each ``--help`` and each ``--json``: examples
in the help that parse, the same placeholder and the same help for the same option, ``--json``
exactly where a command produces a result, ``-v`` exactly where a solver's log can be shown, one
rule for default output folders, and a ``provenance`` record first in every JSON."""

import json
import shlex

import pytest

from scalf_opt.cli import main
from scalf_opt.cli.app import build_parser
from scalf_opt.cli.commands import COMMANDS
from tests.cli.conftest import GAIT_ARGV

PLACEHOLDERS = {"FILE", "DIR", "NAME", "LEG", "N", "X", "URL"}
JSON_COMMANDS = {"model", "evaluate", "optimize", "paper", "simulate", "analyze-log", "variant"}
JSON_COMMANDS |= {"study", "gait"}
VERBOSE_COMMANDS = {"optimize", "paper"}  # the commands that run Ipopt and can show its log
PARSER = build_parser()
SUBPARSERS = PARSER.get_default("commands")
NAMES = [command.NAME for command in COMMANDS]


def options(name):
    return {o: a for a in SUBPARSERS[name]._actions for o in a.option_strings}


@pytest.mark.parametrize("name", NAMES)
def test_every_help_ends_with_examples_that_parse(name, capsys):
    with pytest.raises(SystemExit) as exit_:
        main([name, "--help"])
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    assert "\nexamples:\n" in text
    examples = [
        line.strip() for line in text.split("\nexamples:\n")[1].splitlines() if "scalf-opt" in line
    ]
    assert len(examples) >= 3
    for example in examples:
        argv = shlex.split(example.split("|")[0])[1:]
        PARSER.parse_args(argv)  # exits (code 2) on an example that does not parse


@pytest.mark.parametrize("name", NAMES)
def test_placeholders_are_the_same_few_words(name):
    for action in SUBPARSERS[name]._actions:
        if action.nargs == 0 or action.dest == "help":
            continue
        if action.choices is not None and action.metavar is None:
            continue  # a short list of choices is its own placeholder
        assert action.metavar in PLACEHOLDERS, (name, action.dest, action.metavar)


def test_an_option_means_the_same_in_every_command():
    seen: dict[str, tuple[str, object, str]] = {}
    for name in NAMES:
        for option, action in options(name).items():
            if option in ("--out", "--from", "--period", "--gait", "--cycles", "--leg"):
                continue  # what is written, read or counted differs by command
            if (name, option) == ("export", "--rate"):
                continue  # the rate of the exported samples, not of the gait's grid
            if (name, option) == ("analyze-log", "--speed"):
                continue  # the speed the log was recorded at, not speeds to search
            if name in ("evaluate", "optimize") and option == "--speed":
                continue  # the one speed to walk (the step length follows), the same in both
            if (name, option) == ("gait", "--family"):
                continue  # a gait's trials take swing families only (the next test)
            if (name, option) in (
                ("simulate", "--model"),
                ("export", "--model"),
                ("view", "--model"),
            ):
                continue  # the model of the world the plan is refereed in, read from or shown in
            if (name, option) == ("gait", "--model"):
                continue  # the model each speed is searched in (the same choices as optimize's)
            if (name, option) == ("evaluate", "--model"):
                continue  # the model the reference is evaluated in (3d: balanced, not optimized)
            if (name, option) in (("gait", "--duty"), ("gait", "--rate")):
                continue  # the starts' duty factors and the 3-D grid's rate of every speed
            key = (action.help, action.metavar)
            if option in seen:
                assert seen[option][1:] == key, (option, name, seen[option][0])
            else:
                seen[option] = (name, *key)
    assert {"--urdf", "--robot", "-q", "--debug"} <= set(seen)
    walk = [
        (options(n)["--speed"].help, options(n)["--speed"].metavar)
        for n in ("evaluate", "optimize")
    ]
    assert walk[0] == walk[1]
    # what --from holds: one option, the same words, in the commands that read a 3-D cycle
    source = "what --from holds (default: read from it); 3d: a cycle of optimize --model 3d, "
    for name in ("export", "view"):
        assert options(name)["--model"].help.startswith(source), name


def test_a_help_offers_only_what_its_command_accepts(capsys):
    assert "free" in options("optimize")["--family"].help
    assert "free" not in options("gait")["--family"].help
    assert main(["gait", "--speed", "1", "--family", "free"]) == 2  # refused, as the help says
    assert capsys.readouterr().err.count("\n") == 1
    accounting = options("evaluate")["--accounting"].help
    assert all(f"{name} = " in accounting for name in ("paper", "positive", "regenerative"))
    assert "electric drives meter their own input power" in accounting


@pytest.mark.parametrize("name", NAMES)
def test_json_where_a_result_is_produced_and_verbose_where_a_solver_runs(name):
    have = options(name)
    assert ("--json" in have) == (name in JSON_COMMANDS)
    assert ("-v" in have) == (name in VERBOSE_COMMANDS)


@pytest.mark.parametrize("name", NAMES)
def test_default_output_folders_are_under_results_named_by_the_command(name):
    out = options(name).get("--out")
    if out is None or out.default is None:
        return  # writes only when told where (model, evaluate, optimize, variant, study)
    assert str(out.default).startswith(f"results/{name}"), out.default


def test_study_default_folder_is_under_results_study():
    assert "(default results/study/<study file stem>)" in options("study")["--out"].help


@pytest.mark.xdist_group("cli_runs")  # simulate's and gait's runs are shared with other modules
def test_every_json_starts_with_its_provenance(capsys, tmp_path, simulated, gait_run):
    simulation, printed = simulated  # simulate --cycles 3 --out DIR --log DIR/log.csv --json
    study = tmp_path / "tiny.toml"
    study.write_text('[study]\nrobot = "scalf"\nfamily = "paper"\noptimize = "RF"\n')
    fast = ["--rate", "100"]
    runs = {
        "model": ["model"],
        "evaluate": ["evaluate", *fast],
        "optimize": ["optimize", "--family", "paper", "--leg", "RF", *fast],
        "paper": ["paper", "--quick", *fast, "--out", str(tmp_path / "paper")],
        "simulate": None,  # the shared run: what it printed
        "analyze-log": ["analyze-log", str(simulation / "log.csv")],
        "variant": ["variant", "--thigh-length-scale", "1.1", "--out", str(tmp_path / "v.urdf")],
        "study": ["study", str(study), "--workers", "1", "--out", str(tmp_path / "study")],
        # into the shared run's folder: its case comes from the folder's cache
        "gait": [*GAIT_ARGV, "--out", str(gait_run[0])],
    }
    assert set(runs) == JSON_COMMANDS
    for name, argv in runs.items():
        if argv is None:
            data = printed
        else:
            code = main([*argv, "--json"])
            out, err = capsys.readouterr()
            assert code == 0, (name, err)
            data = json.loads(out)
        assert next(iter(data)) == "provenance", name
        assert data["provenance"]["tool"] == "scalf-opt"
        assert data["provenance"]["command"].startswith(f"scalf-opt {name}")


def test_an_option_without_effect_is_warned_about_once(capsys):
    assert main(["evaluate", "--robot", "hyq", "--accounting", "positive"]) == 0
    err = capsys.readouterr().err  # on stderr; -q would drop it with the other notes
    assert err.count("\n") == 1 and "--accounting positive has no effect on hyq" in err
    assert main(["evaluate", "--robot", "hyq", "-q"]) == 0  # not given: nothing to say
    assert main(["evaluate", "--accounting", "positive", "-q"]) == 0  # SCalf charges it
    assert capsys.readouterr().err == ""
