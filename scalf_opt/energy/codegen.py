"""Compile a CasADi function to native code once, and reuse it from a disk cache.

CasADi evaluates SX functions in a virtual machine; for the hot evaluator the same function is
emitted as C (``casadi.CodeGenerator``), compiled with the system's C compiler and loaded back
with ``casadi.external``. The shared library is cached under a name derived from the SHA-256 of
the C source, so a function is compiled once per machine and later runs load it instantly.

Without a C compiler (or if compiling fails) the original function is returned unchanged: the
results are the same to round-off, only slower.

The cache is bounded: after each compilation, entries unused for :data:`STALE_AFTER_DAYS` (a
library of another CasADi version or compiler is never used again) are removed, then the least
recently used ones until the cache holds at most ``$SCALF_OPT_CACHE_MAX_MB`` (default
:data:`DEFAULT_MAX_MB`). An entry used in the last :data:`IN_USE_S` seconds is never removed, so
that another process can still load what it has just found.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import platform
import shutil
import signal
import subprocess
import time
from pathlib import Path

import casadi as ca

from scalf_opt.files import scratch_folder
from scalf_opt.heartbeat import meanwhile

OPTIMIZATION_FLAG = "-O1"
"""gcc optimisation level: -O1 compiles the evaluator in a few seconds and runs it ~3x faster
than the virtual machine; -O2 takes twice as long to compile for a few per cent more."""


DEFAULT_MAX_MB = 200.0
"""Default bound of the compile cache [MB]: a leg's kernel is 20-200 kB, a robot's 3-D point kernel
2-4 MB; a full test run adds ~20 MB."""

STALE_AFTER_DAYS = 30.0
"""An entry not used for this long is removed [days]."""

IN_USE_S = 600.0
"""An entry used this recently is kept whatever the bound [s]."""

_LIBRARY, _CHECKSUM = ".so", ".sha256"


def cache_dir() -> Path:
    """Where compiled functions are kept: ``$SCALF_OPT_CACHE`` or ``~/.cache/scalf-opt``."""
    env = os.environ.get("SCALF_OPT_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "scalf-opt"


def _compiler() -> str | None:
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name):
            return name
    return None


def _sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _is_intact(library: Path) -> bool:
    """The library exists and matches the checksum written beside it when it was compiled.

    A truncated or overwritten library must never reach ``dlopen``: loading one can crash the
    process instead of raising.
    """
    checksum = library.with_suffix(".sha256")
    try:
        return library.is_file() and checksum.read_text().strip() == _sha256(library)
    except OSError:
        return False


def cache_max_bytes() -> int:
    """The cache's bound: ``$SCALF_OPT_CACHE_MAX_MB`` megabytes, or :data:`DEFAULT_MAX_MB`."""
    text = os.environ.get("SCALF_OPT_CACHE_MAX_MB", "")
    try:
        megabytes = float(text) if text else DEFAULT_MAX_MB
    except ValueError:
        megabytes = DEFAULT_MAX_MB
    return int(max(megabytes, 0.0) * 1e6)


def load_external(name: str, library: Path | None) -> ca.Function | None:
    """Function ``name`` of a compiled ``library``; ``None`` if there is none or it won't load."""
    if library is None:
        return None
    try:
        return ca.external(name, str(library))
    except RuntimeError:  # removed or replaced under us: the caller keeps the VM function
        return None


def compile_function(fn: ca.Function) -> ca.Function:
    """Return a natively compiled copy of ``fn`` (cached), or ``fn`` itself if that fails."""
    return load_external(fn.name(), compile_library(fn.name(), [fn])) or fn


def _size(path: Path) -> int:
    try:
        return path.stat().st_size
    except OSError:
        return 0


def prune_cache(folder: Path | None = None, keep: Path | None = None) -> list[Path]:
    """Remove stale entries, then the least recently used ones beyond the bound.

    Also removes what a killed process left: staged files (``.name.pid``) older than
    :data:`IN_USE_S`, checksums without their library.

    Args:
        folder: The cache (default :func:`cache_dir`).
        keep: A library never to remove (the one just compiled).

    Returns:
        The files removed.
    """
    folder = cache_dir() if folder is None else folder
    now = time.time()
    removed: list[Path] = []

    def remove(path: Path) -> None:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
            removed.append(path)

    try:
        entries = list(folder.iterdir())
    except OSError:
        return removed
    libraries: list[tuple[float, Path]] = []
    for path in entries:
        try:
            age_s = now - path.stat().st_mtime
        except OSError:
            continue
        staged = path.name.startswith(".")
        orphan = path.suffix == _CHECKSUM and not path.with_suffix(_LIBRARY).exists()
        if staged or orphan:
            if age_s > IN_USE_S:
                remove(path)
        elif path.suffix == _LIBRARY:
            libraries.append((age_s, path))
    libraries.sort(reverse=True)  # least recently used first
    total = sum(_size(p) + _size(p.with_suffix(_CHECKSUM)) for _, p in libraries)
    bound = cache_max_bytes()
    for age_s, library in libraries:
        stale = age_s > STALE_AFTER_DAYS * 86400.0
        if library == keep or age_s < IN_USE_S or not (stale or total > bound):
            continue
        total -= _size(library) + _size(library.with_suffix(_CHECKSUM))
        remove(library)
        remove(library.with_suffix(_CHECKSUM))
    return removed


def _run_compiler(command: list[str], tmp: Path) -> None:
    """Run the compiler with its scratch files in ``tmp``; on Ctrl-C or SIGTERM, stop all of it.

    The compiler runs in its own process group, so that an interruption kills its helper
    processes too (``cc1``, ``as``, ``ld``), and none is left writing after we removed ``tmp``.

    Raises:
        subprocess.CalledProcessError: The compiler failed.
    """
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env={**os.environ, "TMPDIR": str(tmp)},
        start_new_session=True,
    )
    try:
        out, err = process.communicate()
    except BaseException:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
        raise
    if process.returncode != 0:
        raise subprocess.CalledProcessError(process.returncode, command, out, err)


def compile_library(name: str, functions: list[ca.Function]) -> Path | None:
    """Compile ``functions`` into one shared library (cached); ``None`` if that is impossible.

    Load a function from it with ``casadi.external(fn.name(), str(path))``. A library that
    also holds a function's derivative functions under CasADi's names (``jac_f``, ``adj1_f``,
    ``jac_adj1_f``, ...) gives the loaded function those derivatives, so that it can be
    differentiated inside an expression graph (the NLP maps its per-sample function this way).

    Args:
        name: Stem of the library's file name and of its C source.
        functions: The functions, each under its own name.
    """
    compiler = _compiler()
    if compiler is None:
        return None
    with scratch_folder("compile") as folder:
        tmp = str(folder)
        gen = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        for fn in functions:
            gen.add(fn)
        gen.generate(tmp + os.sep)
        source_path = Path(tmp, f"{name}.c")
        # the library depends on the source, the flags, the compiler, the machine and CasADi
        key = f"{OPTIMIZATION_FLAG}|{compiler}|{platform.machine()}|{ca.CasadiMeta.version()}"
        digest = hashlib.sha256(source_path.read_bytes() + key.encode()).hexdigest()[:20]
        target = cache_dir() / f"{name}_{digest}{_LIBRARY}"
        if _is_intact(target):
            with contextlib.suppress(OSError):
                os.utime(target)  # its last use: the least recently used go first
        else:
            try:
                target.parent.mkdir(parents=True, exist_ok=True)
                partial = Path(tmp, target.name)
                command = [compiler, OPTIMIZATION_FLAG, "-shared", "-fPIC", "-o", str(partial)]
                with meanwhile(f"compiling {name} (once per machine)"):
                    _run_compiler([*command, str(source_path), "-lm"], Path(tmp))
                # atomic publish (another process may compile the same function): the library
                # first, then its checksum, so a reader never trusts a partial file
                for src, dst, text in (
                    (partial, target, None),
                    (None, target.with_suffix(_CHECKSUM), _sha256(partial)),
                ):
                    staged = dst.with_name(f".{dst.name}.{os.getpid()}")
                    if src is not None:
                        shutil.copyfile(src, staged)
                    else:
                        staged.write_text(str(text))
                    os.replace(staged, dst)
            except (OSError, subprocess.CalledProcessError):
                return None
            prune_cache(target.parent, keep=target)
    return target
