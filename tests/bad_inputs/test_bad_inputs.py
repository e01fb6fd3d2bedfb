"""The bad-input corpus (cases.toml): one line, exit code 2, the documented error, nothing written.

A case's command runs twice: through ``scalf-opt`` (``main``), which must print exactly one line
on stderr and return 2 without a traceback, and through the command's own function, which must
raise the case's exception type: what an API caller catches.
"""

import re
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


def materialize(case, tmp_path):
    """Write the case's files; return the argv with its placeholders filled."""
    names = {"out": str(tmp_path / "out"), "keep": str(tmp_path / "keep")}
    keep = tmp_path / "keep"
    keep.mkdir()
    (keep / "summary.json").write_text("previous")
    for spec in case.get("files", []):
        path = tmp_path / "in" / spec["name"]
        path.parent.mkdir(parents=True, exist_ok=True)
        if "hex" in spec:
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
    if case["error"] == "usage":
        with pytest.raises(SystemExit) as info:
            main(argv)
        code = info.value.code
    else:
        code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and err.startswith("scalf-opt: error: "), err
    assert "Traceback" not in err
    assert re.search(case["message"], err), f"{case['message']!r} not in {err!r}"
    assert untouched(tmp_path)
    if case["error"] != "usage":
        args, _ = build_parser().parse_known_args(argv)
        args.console, args.argv = Console(quiet=True), ["scalf-opt", *argv]
        with pytest.raises(getattr(errors, case["error"])):
            args.run(args)
        assert untouched(tmp_path)
