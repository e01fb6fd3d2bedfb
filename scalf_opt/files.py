"""The file handling every layer shares: untrusted inputs in, output sets out.

Inputs (:func:`read_untrusted`): every file a user hands scalf-opt (gait, study, legs and actuator
files, URDF, SRDF, ``summary.json``, logs, meshes) is read by one function that accepts regular
files only (a FIFO, a device such as ``/dev/zero``, a terminal or a directory is refused before it
is read, whatever symbolic link leads to it) and reads at most a bound of bytes, counted as they
are read (the size the file system reports is never trusted).

Outputs: a file is first written next to its destination under a temporary name and then renamed
over it (``os.replace``), so a reader never sees a half-written file. A command's files form an
*output set* (:func:`output_set`): they are staged in a temporary folder beside the target and
moved into place together once the command succeeded, so a result folder is complete or left as
it was; a lock refuses a second writer to the same target; only regular files are replaced; what
a killed run left is removed by the next run; a full disk or a denied permission is a
:class:`~scalf_opt.errors.ConfigError` naming the path.

Scratch folders (:func:`scratch_folder`) carry the process id in their name, so that the next run
removes those a killed process left in the temporary folder.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import math
import os
import re
import shutil
import stat
import sys
import tempfile
import tomllib
from collections.abc import Callable, Iterable, Iterator
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from scalf_opt.errors import ConfigError, ScalfError

MAX_TOML_BYTES = 1024 * 1024
"""Largest configuration file read (gait, study, legs, actuator files) [bytes]; real ones are a
few kB."""

_READ_BLOCK = 1 << 20


def _kind_of(mode: int) -> str:
    """What a non-regular file is, for messages."""
    for test, name in (
        (stat.S_ISREG, "a regular file"),
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return name
    return "not a regular file"


def read_untrusted(
    path: str | Path, kind: str, max_bytes: int, error: type[ScalfError] = ConfigError
) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``; ``kind`` names it in messages.

    The file is checked to be a regular file before it is opened (opening a FIFO would wait for
    a writer) and again once open (it cannot be swapped in between), opened without blocking and
    without becoming a controlling terminal, and read in blocks until its end or one byte past
    the bound: a file that grows while read, or that reports a wrong size, is still bounded.

    Raises:
        ScalfError: (of type ``error``) The file is missing, not a regular file, unreadable or
            larger than ``max_bytes``; the message names the file.
    """
    path = Path(path)
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):
            raise error(f"{path}: {kind} file is {_kind_of(info.st_mode)}, not a regular file")
        flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0) | os.O_CLOEXEC
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise error(f"{path}: {kind} file not found") from None
    except OSError as exc:
        raise error(f"{path}: cannot read {kind} file ({exc.strerror})") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise error(f"{path}: {kind} file is {_kind_of(info.st_mode)}, not a regular file")
        chunks: list[bytes] = []
        total = 0
        while True:
            chunk = os.read(fd, min(_READ_BLOCK, max_bytes + 1 - total))
            if not chunk:
                break
            total += len(chunk)
            if total > max_bytes:
                raise error(f"{path}: {kind} file is larger than the {max_bytes} bytes allowed")
            chunks.append(chunk)
    except OSError as exc:
        raise error(f"{path}: cannot read {kind} file ({exc.strerror})") from None
    finally:
        os.close(fd)
    return b"".join(chunks)


def copy_untrusted(
    source: str | Path,
    destination: Path,
    kind: str,
    max_bytes: int,
    error: type[ScalfError] = ConfigError,
) -> int:
    """Copy a regular file of at most ``max_bytes`` to ``destination``, block by block.

    For a library that reads files by path only (a ROS 2 bag reader): it is given the bounded
    copy, in a private folder. The checks are :func:`read_untrusted`'s.

    Returns:
        The bytes copied.

    Raises:
        ScalfError: (of type ``error``) See :func:`read_untrusted`.
    """
    source = Path(source)
    try:
        info = os.stat(source)
        if not stat.S_ISREG(info.st_mode):
            raise error(f"{source}: {kind} file is {_kind_of(info.st_mode)}, not a regular file")
        fd = os.open(source, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise error(f"{source}: {kind} file not found") from None
    except OSError as exc:
        raise error(f"{source}: cannot read {kind} file ({exc.strerror})") from None
    total = 0
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise error(f"{source}: {kind} file is not a regular file")
        with _scratch_file(destination, kind, error) as out:
            while chunk := os.read(fd, min(_READ_BLOCK, max_bytes + 1 - total)):
                total += len(chunk)
                if total > max_bytes:
                    raise error(
                        f"{source}: {kind} file is larger than the {max_bytes} bytes allowed"
                    )
                _write_scratch(out, chunk, kind, error)
    except OSError as exc:
        raise error(f"{source}: cannot read {kind} file ({exc.strerror})") from None
    finally:
        os.close(fd)
    return total


@contextlib.contextmanager
def _scratch_file(path: Path, kind: str, error: type[ScalfError]) -> Iterator[IO[bytes]]:
    """``path`` opened for writing a private copy.

    Failing to open, write or close it is the temporary folder's fault (a full disk), not the
    input's, and the message says so.
    """
    try:
        handle = open(path, "wb")  # noqa: SIM115  (closed below)
    except OSError as exc:
        raise error(_scratch_message(kind, exc)) from None
    try:
        yield handle
    finally:
        try:
            handle.close()  # flushes: a full disk may say so only here
        except OSError as exc:
            raise error(_scratch_message(kind, exc)) from None


def _write_scratch(out: IO[bytes], chunk: bytes, kind: str, error: type[ScalfError]) -> None:
    try:
        out.write(chunk)
    except OSError as exc:
        raise error(_scratch_message(kind, exc)) from None


def _scratch_message(kind: str, exc: OSError) -> str:
    return (
        f"cannot copy the {kind} into the temporary folder {tempfile.gettempdir()} "
        f"({exc.strerror}): free space there, or set TMPDIR to a folder with room"
    )


def read_untrusted_text(
    path: str | Path, kind: str, max_bytes: int, error: type[ScalfError] = ConfigError
) -> str:
    """:func:`read_untrusted`, decoded as UTF-8.

    Raises:
        ScalfError: See :func:`read_untrusted`; or the file is not UTF-8 text.
    """
    data = read_untrusted(path, kind, max_bytes, error)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{path}: {kind} file is not UTF-8 text (byte {exc.start})") from None


def read_toml(path: Path, kind: str) -> dict[str, Any]:
    """Parse ``path``; ``kind`` names the file in messages (``gait``, ``actuator``).

    Raises:
        ConfigError: The file cannot be read, is not a regular file, is larger than
            :data:`MAX_TOML_BYTES`, is not UTF-8 text or not valid TOML (the message names the
            file).
    """
    text = read_untrusted_text(path, kind, MAX_TOML_BYTES)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc
    except ValueError:  # an integer of more digits than Python converts (4300)
        raise ConfigError(f"{path}: a number in the TOML has too many digits") from None
    except RecursionError:
        raise ConfigError(f"{path}: not valid TOML (nested too deeply)") from None


# --- scratch folders ----------------------------------------------------------------------------

SCRATCH_PREFIX = "scalf-opt-"
_SCRATCH = re.compile(r"^scalf-opt-[a-z]+-(\d+)-")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # another user's process
    return True


def remove_stale_scratch(
    folder: str | Path | None = None, pids: Iterable[int] | None = None
) -> list[Path]:
    """Remove the scratch folders (:func:`scratch_folder`) of processes that no longer run.

    ``pids``: only those of these processes (a command's own worker processes, once ended).
    """
    folder = Path(tempfile.gettempdir() if folder is None else folder)
    only = None if pids is None else set(pids)
    removed: list[Path] = []
    try:
        entries = list(folder.iterdir())
    except OSError:
        return removed
    for path in entries:
        match = _SCRATCH.match(path.name)
        pid = int(match.group(1)) if match else None
        if pid is None or (only is not None and pid not in only):
            continue
        if pid != os.getpid() and not _alive(pid):
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
    return removed


@contextlib.contextmanager
def scratch_folder(kind: str) -> Iterator[Path]:
    """A private temporary folder, removed on exit.

    Its name carries the process id, so that the next run removes it if this process is killed
    (:func:`remove_stale_scratch`).
    """
    with tempfile.TemporaryDirectory(prefix=f"{SCRATCH_PREFIX}{kind}-{os.getpid()}-") as tmp:
        yield Path(tmp)


# --- writing ------------------------------------------------------------------------------------


def number_text(x: float) -> str:
    """A number as the files scalf-opt writes show it (CSV cells, generated URDF values).

    Fifteen significant digits, the most a double keeps through text, written as the shortest
    text that reads back to them: ``0.45099`` for the sum that is ``0.45099000000000006`` in
    full (the round-off of arithmetic, not a digit of the value); ``nan`` for NaN.
    """
    x = float(x)
    return "nan" if math.isnan(x) else repr(float(f"{x:.15g}"))


def _writing_error(path: Path, exc: OSError) -> ConfigError:
    reason = exc.strerror or type(exc).__name__
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        reason += ": free some space and run again"
    return ConfigError(f"{path}: cannot write ({reason})")


_TMP_FILE = re.compile(r"^\..+\.[A-Za-z0-9_]{8}\.tmp$")
"""The temporary files of :func:`write_with` (``.name.XXXXXXXX.tmp``)."""


def temporary_sibling(path: Path, shown: Path | None = None) -> tuple[int, str]:
    """Open a temporary file beside ``path`` with the permissions a new file would get.

    ``mkstemp`` creates files readable by their owner only; outputs should be as readable as any
    file the user creates, so the mode follows the umask.

    Raises:
        ConfigError: The directory cannot be created or written.
    """
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{_short(path.name)}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise _writing_error((shown or path).parent, exc) from exc
    os.fchmod(fd, 0o666 & ~_umask())
    return fd, tmp


def _umask() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _short(name: str, limit: int = 100) -> str:
    """``name``, or a short stand-in for a name too long to be a prefix of a file name."""
    if len(name.encode()) <= limit:
        return name
    return name[:40] + "-" + hashlib.sha256(name.encode()).hexdigest()[:16]


def _refuse_non_regular(path: Path, shown: Path | None = None) -> None:
    """Refuse to replace ``path`` when it exists and is not a regular file."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return
    except OSError as exc:
        raise _writing_error(shown or path, exc) from exc
    if not stat.S_ISREG(info.st_mode):
        raise ConfigError(
            f"{shown or path}: is {_kind_of(info.st_mode)}; only a regular file is replaced"
        )


def write_with(path: str | Path, write: Callable[[IO[bytes]], None]) -> Path:
    """Write ``path`` atomically: ``write`` fills a temporary sibling, which is then renamed.

    Inside an :func:`output_set` whose target holds ``path``, the file is written into the set's
    staging folder instead and moved into place with the others when the set is complete.

    Raises:
        ConfigError: ``path`` is not a regular file, or cannot be written (a full disk, a denied
            permission, a name too long); the message names it.
    """
    path = Path(path)
    shown = path
    staged = _staged_location(path)
    if staged is None:
        _refuse_non_regular(path)
    else:
        path = staged
    fd, tmp = temporary_sibling(path, shown)
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise _writing_error(shown, exc) from exc
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return shown


def write_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    data = text.encode("utf-8")

    def write(handle: IO[bytes]) -> None:
        handle.write(data)

    return write_with(path, write)


# --- output sets --------------------------------------------------------------------------------


@dataclass
class _Target:
    """One target of an output set: a folder (every file under it) or one file."""

    path: Path
    folder: bool
    direct: tuple[Path, ...] = ()
    stage: Path | None = None
    lock_fd: int | None = None
    lock_path: Path | None = None
    given: Path | None = None
    """The path as the user gave it, for messages (``path`` is absolute)."""

    def holds(self, path: Path) -> Path | None:
        """``path`` relative to the target when the set stages it, else ``None``."""
        if self.folder:
            if not path.is_relative_to(self.path) or path == self.path:
                return None
            if any(path.is_relative_to(d) for d in self.direct):
                return None
            return path.relative_to(self.path)
        return Path(self.path.name) if path == self.path else None


@dataclass
class OutputSet:
    """The files a command writes, staged and moved into place together (:func:`output_set`)."""

    targets: list[_Target] = field(default_factory=list)

    def staged(self, path: Path) -> Path | None:
        """Where ``path`` is staged, or ``None`` when no target holds it."""
        for target in self.targets:
            relative = target.holds(path)
            if relative is not None:
                if target.stage is None:
                    # files side by side share a stage: staged, they are side by side too
                    beside = [
                        t.stage
                        for t in self.targets
                        if not t.folder
                        and not target.folder
                        and t.path.parent == target.path.parent
                    ]
                    shared = next((stage for stage in beside if stage is not None), None)
                    target.stage = shared or _new_stage(target.path)
                return target.stage / relative
        return None


_ACTIVE: ContextVar[tuple[OutputSet, ...]] = ContextVar("scalf_opt_output_sets", default=())


def _absolute(path: str | Path) -> Path:
    return Path(os.path.abspath(path))


def _existing_ancestor(path: Path) -> Path:
    folder = path.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    return folder


def _new_stage(target: Path) -> Path:
    home = _existing_ancestor(target)
    try:
        stage = Path(tempfile.mkdtemp(prefix=f".{_short(target.name)}.stage-", dir=home))
        os.chmod(stage, 0o777 & ~_umask())  # it may become the output folder: a folder's mode
    except OSError as exc:
        raise _writing_error(target, exc) from exc
    return stage


def _staged_location(path: Path) -> Path | None:
    absolute = _absolute(path)
    for active in reversed(_ACTIVE.get()):
        staged = active.staged(absolute)
        if staged is not None:
            return staged
    return None


def current_location(path: str | Path) -> Path:
    """Where a file this command wrote is now: in its output set's staging folder, or ``path``."""
    staged = _staged_location(Path(path))
    return staged if staged is not None and staged.exists() else Path(path)


def _lock(target: _Target) -> None:
    """Take the target's lock (a file beside it), or refuse: another run writes the target."""
    home = _existing_ancestor(target.path)
    relative = os.path.relpath(target.path, home).replace(os.sep, "%")
    lock = home / f".{_short(relative)}.scalf-opt.lock"
    for _ in range(10):
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
        except OSError as exc:
            raise _writing_error(target.path, exc) from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise ConfigError(
                f"{target.given or target.path}: another scalf-opt run is writing it; wait "
                "until it ends"
            ) from None
        try:
            same = os.fstat(fd).st_ino == os.stat(lock).st_ino
        except FileNotFoundError:
            same = False
        if same:
            target.lock_fd, target.lock_path = fd, lock
            return
        os.close(fd)  # the previous holder removed it as we opened it: take the new one
    raise ConfigError(f"{target.path}: cannot take its lock {lock}")


def _unlock(target: _Target) -> None:
    if target.lock_fd is None or target.lock_path is None:
        return
    with contextlib.suppress(OSError):
        target.lock_path.unlink()
    os.close(target.lock_fd)
    target.lock_fd = None


def _remove_leftovers(target: _Target) -> None:
    """Remove what a killed run left for this target: staging folders and temporary files.

    Temporary files are looked for in the target folder and its subfolders one level down (a
    study's cache), beside a target file: never in a whole tree the user named by mistake.
    """
    home = _existing_ancestor(target.path)
    prefix = f".{_short(target.path.name)}.stage-"
    with contextlib.suppress(OSError):
        for entry in home.iterdir():
            if entry.name.startswith(prefix) and entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry, ignore_errors=True)
    if target.folder:
        folders = [target.path]
        with contextlib.suppress(OSError):
            folders += [p for p in target.path.iterdir() if p.is_dir() and not p.is_symlink()]
        own = ""
    else:
        folders, own = [target.path.parent], f".{_short(target.path.name)}."
    for folder in folders:
        with contextlib.suppress(OSError):
            for entry in folder.iterdir():
                ours = _TMP_FILE.match(entry.name) and entry.name.startswith(own)
                if ours and entry.is_file() and not entry.is_symlink():
                    entry.unlink(missing_ok=True)


def _check_target(target: _Target) -> None:
    path = target.path
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return
    except OSError as exc:
        raise _writing_error(path, exc) from exc
    if target.folder and not stat.S_ISDIR(info.st_mode):
        raise ConfigError(f"{path}: is {_kind_of(info.st_mode)}, not a folder")
    if not target.folder and not stat.S_ISREG(info.st_mode):
        raise ConfigError(f"{path}: is {_kind_of(info.st_mode)}; only a regular file is replaced")


def _staged_files(stage: Path) -> list[Path]:
    return sorted(
        Path(root, name).relative_to(stage) for root, _, names in os.walk(stage) for name in names
    )


def _step(
    move: Callable[[Path, Path], None], source: Path, destination: Path
) -> Callable[[], None]:
    return lambda: move(source, destination)


def _commit(targets: list[_Target]) -> None:
    """Move every staged file into place; on a failure, put back what was there before."""
    moves: list[tuple[_Target, Path, Path]] = []  # (target, staged file, destination)
    for target in targets:
        if target.stage is None:
            continue
        if target.folder:
            pairs = [(target.stage / r, target.path / r) for r in _staged_files(target.stage)]
        else:
            pairs = [(target.stage / target.path.name, target.path)]
        for source, destination in pairs:
            if source.exists():
                _refuse_non_regular(destination)
                moves.append((target, source, destination))
    undo: list[Callable[[], None]] = []
    try:
        for target in targets:
            stage = target.stage
            if stage is None:
                continue
            if target.folder and not target.path.exists():
                target.path.parent.mkdir(parents=True, exist_ok=True)
                os.rename(stage, target.path)  # the whole folder at once
                undo.append(_step(os.rename, target.path, stage))
                continue
            for owner, staged, destination in moves:
                if owner is not target:
                    continue
                destination.parent.mkdir(parents=True, exist_ok=True)
                if destination.exists():
                    backup = stage / ".previous" / staged.relative_to(stage)
                    backup.parent.mkdir(parents=True, exist_ok=True)
                    os.replace(destination, backup)
                    undo.append(_step(os.replace, backup, destination))
                else:
                    undo.append(_step(os.replace, destination, staged))
                os.replace(staged, destination)
    except OSError as exc:
        for step in reversed(undo):
            with contextlib.suppress(OSError):
                step()
        raise _writing_error(_shown(targets, exc.filename), exc) from exc


def _shown(targets: list[_Target], filename: str | None) -> Path:
    """The user's path for a path in a staging folder (the target's), for messages."""
    path = Path(filename) if filename else targets[0].path
    for target in targets:
        if target.stage is not None and path.is_relative_to(target.stage):
            relative = path.relative_to(target.stage)
            return target.path / relative if target.folder else target.path
    return path


@contextlib.contextmanager
def output_set(
    folders: Iterable[str | Path | None] = (),
    files: Iterable[str | Path | None] = (),
    direct: Iterable[str | Path] = (),
) -> Iterator[OutputSet]:
    """Stage every file written under ``folders`` or to ``files`` and move them in together.

    Entering takes each target's lock (a ``.<name>.scalf-opt.lock`` file beside it, removed on
    exit), refuses a target that is of the wrong kind (a folder that is a file, a file that is
    a device or a folder), and removes what killed runs left for the target. Inside, every
    :func:`write_with` to a path of a target goes to a staging folder beside it. On a normal
    exit the staged files are moved into place: a new folder by one rename, into an existing
    folder file by file, with the previous files put back if a move fails. On an exception the
    staging folder is removed and the targets are left as they were.

    Args:
        folders: Output folders (``None`` entries are skipped).
        files: Output files.
        direct: Paths under a folder that are written in place at once, not staged (a study's
            cache of finished cases, which a killed run must keep).

    Raises:
        ConfigError: A target is of the wrong kind, another run holds its lock, or it cannot be
            written (the message names it).
    """
    direct_paths = tuple(_absolute(p) for p in direct)
    targets = [
        _Target(_absolute(p), True, direct_paths, given=Path(p)) for p in folders if p is not None
    ]
    targets += [_Target(_absolute(p), False, given=Path(p)) for p in files if p is not None]
    outputs = OutputSet(targets)
    try:
        for target in targets:
            _check_target(target)
            _lock(target)
            _remove_leftovers(target)
        token = _ACTIVE.set((*_ACTIVE.get(), outputs))
        try:
            yield outputs
            _commit(targets)
        finally:
            _ACTIVE.reset(token)
    finally:
        for target in targets:
            if target.stage is not None:
                shutil.rmtree(target.stage, ignore_errors=True)
            _unlock(target)


# --- native output ------------------------------------------------------------------------------


@contextlib.contextmanager
def captured_native_output(fds: tuple[int, ...] = (1, 2)) -> Iterator[list[str]]:
    """Catch what native libraries print on file descriptors 1 and 2, instead of the terminal.

    urdfdom prints its parser errors there, assimp its warnings, with install paths and on
    several lines; the command line turns them into its one line.

    Yields a list that holds, on exit, the non-empty lines caught (for the one-line error that
    replaces them).
    """
    lines: list[str] = []
    with contextlib.ExitStack() as stack:
        saved = []
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except (OSError, ValueError):
            pass
        capture = stack.enter_context(tempfile.TemporaryFile())
        for fd in fds:
            try:
                saved.append((fd, os.dup(fd)))
                os.dup2(capture.fileno(), fd)
            except OSError:
                continue
        try:
            yield lines
        finally:
            for fd, copy in saved:
                os.dup2(copy, fd)
                os.close(copy)
            capture.seek(0)
            text = capture.read(1 << 20).decode("utf-8", errors="replace")
            lines.extend(line.strip() for line in text.splitlines() if line.strip())
