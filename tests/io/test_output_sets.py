"""Untrusted files in, output sets out: the file handling of scalf_opt.files."""

import errno
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from scalf_opt import files
from scalf_opt.errors import ConfigError, ModelError
from scalf_opt.files import (
    current_location,
    output_set,
    read_untrusted,
    remove_stale_scratch,
    scratch_folder,
    write_atomic,
)

# --- the reader ---------------------------------------------------------------------------------


def test_the_reader_counts_bytes_and_does_not_trust_the_reported_size():
    # /proc files are regular files that report a size of 0 and hold more
    status = Path("/proc/self/status")
    if not status.exists():
        pytest.skip("no /proc")
    assert status.stat().st_size == 0
    assert len(read_untrusted(status, "status", 1 << 20)) > 100
    with pytest.raises(ConfigError, match="status file is larger than the 10 bytes allowed"):
        read_untrusted(status, "status", 10)


@pytest.mark.parametrize(
    ("make", "kind"),
    [
        (lambda p: p.symlink_to("/dev/zero"), "a character device"),
        (lambda p: os.mkfifo(p), "a named pipe"),
        (lambda p: p.mkdir(), "a directory"),
    ],
)
def test_the_reader_takes_regular_files_only(tmp_path, make, kind):
    path = tmp_path / "input"
    make(path)
    with pytest.raises(ModelError, match=f"input: URDF file is {kind}"):
        read_untrusted(path, "URDF", 1000, ModelError)


def test_the_reader_names_a_missing_file(tmp_path):
    with pytest.raises(ConfigError, match=r"none\.toml: gait file not found"):
        read_untrusted(tmp_path / "none.toml", "gait", 1000)


# --- output sets --------------------------------------------------------------------------------


def _entries(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_a_set_appears_whole_when_its_command_ends(tmp_path):
    out = tmp_path / "out"
    with output_set(folders=[out]):
        write_atomic(out / "a.txt", "a")
        write_atomic(out / "sub" / "b.txt", "b")
        assert not out.exists()  # staged beside it until the command ends
        assert current_location(out / "a.txt").read_text() == "a"
    assert (out / "a.txt").read_text() == "a" and (out / "sub" / "b.txt").read_text() == "b"
    assert _entries(tmp_path) == ["out"]  # no stage, no lock left
    assert oct(out.stat().st_mode & 0o777) == oct(0o777 & ~files._umask())


def test_a_failed_command_leaves_the_previous_set(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.txt").write_text("previous a")
    (out / "mine.txt").write_text("the user's")
    with (
        pytest.raises(RuntimeError),
        output_set(folders=[out]),
    ):
        write_atomic(out / "a.txt", "new a")
        write_atomic(out / "b.txt", "new b")
        raise RuntimeError("the command failed half-way")
    assert _entries(out) == ["a.txt", "mine.txt"] and (out / "a.txt").read_text() == "previous a"
    assert _entries(tmp_path) == ["out"]


def test_a_set_replaces_files_into_an_existing_folder_and_keeps_the_others(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.txt").write_text("previous a")
    (out / "mine.txt").write_text("the user's")
    with output_set(folders=[out]):
        write_atomic(out / "a.txt", "new a")
    assert (out / "a.txt").read_text() == "new a" and (out / "mine.txt").read_text() == "the user's"


def test_a_move_that_fails_puts_the_previous_files_back(tmp_path, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    for name in ("a.txt", "b.txt"):
        (out / name).write_text(f"previous {name}")
    real = os.replace
    calls = []

    def failing(src, dst):
        calls.append(dst)
        if len(calls) == 4:  # a's backup and move, b's backup, then b's move fails
            raise OSError(errno.ENOSPC, "No space left on device", str(dst))
        return real(src, dst)

    with (
        pytest.raises(ConfigError, match=r"b.txt: cannot write \(No space left on device"),
        output_set(folders=[out]),
    ):
        write_atomic(out / "a.txt", "new a")
        write_atomic(out / "b.txt", "new b")
        monkeypatch.setattr(os, "replace", failing)
    monkeypatch.setattr(os, "replace", real)
    assert {p.name: p.read_text() for p in out.iterdir()} == {
        "a.txt": "previous a.txt",
        "b.txt": "previous b.txt",
    }
    assert _entries(tmp_path) == ["out"]


def test_a_full_disk_is_bad_input_naming_the_file(tmp_path, monkeypatch):
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    out = tmp_path / "out"
    with (
        pytest.raises(ConfigError, match=r"out/a.txt: cannot write \(No space left on device"),
        output_set(folders=[out]),
    ):
        write_atomic(out / "a.txt", "a")
    assert _entries(tmp_path) == []


def test_a_second_writer_is_refused(tmp_path):
    out = tmp_path / "out"
    with output_set(folders=[out]):
        with (
            pytest.raises(ConfigError, match="another scalf-opt run is writing it"),
            output_set(folders=[out]),
        ):
            pass
        code = (
            "import sys; from scalf_opt.cli import main; "
            f"sys.exit(main(['evaluate', '--out', {str(out)!r}, '-q']))"
        )
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert done.returncode == 2 and "another scalf-opt run is writing it" in done.stderr
    with output_set(folders=[out]):  # free again
        pass


def test_only_regular_files_are_replaced(tmp_path):
    os.mkfifo(tmp_path / "pipe.csv")
    with (
        pytest.raises(ConfigError, match=r"pipe\.csv: is a named pipe"),
        output_set(files=[tmp_path / "pipe.csv"]),
    ):
        pass
    with pytest.raises(ConfigError, match="null: is a character device"):
        write_atomic("/dev/null", "x")
    (tmp_path / "file").write_text("x")
    with (
        pytest.raises(ConfigError, match="file: is a regular file, not a folder"),
        output_set(folders=[tmp_path / "file"]),
    ):
        pass


def test_what_a_killed_run_left_is_removed_by_the_next(tmp_path):
    out = tmp_path / "out"
    (out / "cache").mkdir(parents=True)
    stale = [
        tmp_path / ".out.stage-abc12345",
        out / ".summary.json.abcd1234.tmp",
        out / "cache" / ".k.json.abcd1234.tmp",
    ]
    stale[0].mkdir()
    for path in stale[1:]:
        path.write_text("half")
    (out / "keep.tmp").write_text("not ours")
    with output_set(folders=[out], direct=[out / "cache"]):
        write_atomic(out / "cache" / "k.json", "at once")  # the cache is written in place
        assert (out / "cache" / "k.json").exists()
    assert not any(p.exists() for p in stale) and (out / "keep.tmp").exists()


def test_scratch_folders_of_dead_processes_are_removed(tmp_path):
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], text=True, capture_output=True
    ).stdout.strip()
    (tmp_path / f"scalf-opt-case-{dead}-abc").mkdir()
    (tmp_path / f"scalf-opt-case-{os.getpid()}-abc").mkdir()
    (tmp_path / "scalf-opt-case-1-abc").mkdir()  # init: alive
    removed = remove_stale_scratch(tmp_path)
    assert [p.name for p in removed] == [f"scalf-opt-case-{dead}-abc"]
    with scratch_folder("x") as folder:
        assert folder.name.startswith(f"scalf-opt-x-{os.getpid()}-")
    assert not folder.exists()


# --- signals whatever the library does with them ------------------------------------------------


def test_a_signal_a_library_turned_into_its_own_error_still_ends_143(capsys):
    """CasADi turns the exception a signal handler raises inside a callback into a
    RuntimeError; the command line still ends as the signal says, without a traceback."""
    from scalf_opt.cli import app
    from scalf_opt.cli.console import Console

    def command(args):
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            signal.sigtimedwait([], 0) if hasattr(signal, "sigtimedwait") else None
        except SystemExit as exc:
            raise RuntimeError("NonIpopt_Exception_Thrown") from exc
        return 0

    parser = app.build_parser()
    args = parser.parse_args(["model"])
    args.run, args.outputs = command, None
    with app.stop_on_signals():
        code = app._run(args, ["model"], Console())
    err = capsys.readouterr().err
    assert code == 143 and err == "scalf-opt: error: terminated\n"


def test_files_side_by_side_are_staged_side_by_side(tmp_path):
    """A variant's URDF is read back, during the command, with its actuator file beside it."""
    urdf, beside = tmp_path / "v" / "v.urdf", tmp_path / "v" / "v_actuators.toml"
    with output_set(files=[urdf, beside]):
        write_atomic(urdf, "<robot/>")
        write_atomic(beside, "[cylinders]")
        staged = current_location(urdf)
        assert staged != urdf and (staged.parent / beside.name).read_text() == "[cylinders]"
        assert not urdf.exists()
    assert urdf.read_text() == "<robot/>" and beside.read_text() == "[cylinders]"
    assert _entries(tmp_path / "v") == ["v.urdf", "v_actuators.toml"]
