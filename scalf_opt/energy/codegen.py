"""Compile a CasADi function to native code once, and reuse it from a disk cache.

CasADi evaluates SX functions in a virtual machine; for the hot evaluator the same function is
emitted as C (``casadi.CodeGenerator``), compiled with the system's C compiler and loaded back
with ``casadi.external``. The shared library is cached under a name derived from the SHA-256 of
the C source, so a function is compiled once per machine and later runs load it instantly.

Without a C compiler (or if compiling fails) the original function is returned unchanged: the
results are the same to round-off, only slower.
"""

from __future__ import annotations

import hashlib
import os
import platform
import shutil
import subprocess
import tempfile
from pathlib import Path

import casadi as ca

OPTIMIZATION_FLAG = "-O1"
"""gcc optimisation level: -O1 compiles the evaluator in a few seconds and runs it ~3x faster
than the virtual machine; -O2 takes twice as long to compile for a few per cent more."""


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


def compile_function(fn: ca.Function) -> ca.Function:
    """Return a natively compiled copy of ``fn`` (cached), or ``fn`` itself if that fails."""
    library = compile_library(fn.name(), [fn])
    return fn if library is None else ca.external(fn.name(), str(library))


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
    with tempfile.TemporaryDirectory() as tmp:
        gen = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        for fn in functions:
            gen.add(fn)
        gen.generate(tmp + os.sep)
        source_path = Path(tmp, f"{name}.c")
        # the library depends on the source, the flags, the compiler, the machine and CasADi
        key = f"{OPTIMIZATION_FLAG}|{compiler}|{platform.machine()}|{ca.CasadiMeta.version()}"
        digest = hashlib.sha256(source_path.read_bytes() + key.encode()).hexdigest()[:20]
        target = cache_dir() / f"{name}_{digest}.so"
        if not _is_intact(target):
            try:
                target.parent.mkdir(parents=True, exist_ok=True)
                partial = Path(tmp, target.name)
                command = [compiler, OPTIMIZATION_FLAG, "-shared", "-fPIC", "-o", str(partial)]
                subprocess.run([*command, str(source_path), "-lm"], check=True, capture_output=True)
                # atomic publish (another process may compile the same function): the library
                # first, then its checksum, so a reader never trusts a partial file
                for src, dst, text in (
                    (partial, target, None),
                    (None, target.with_suffix(".sha256"), _sha256(partial)),
                ):
                    staged = dst.with_name(f".{dst.name}.{os.getpid()}")
                    if src is not None:
                        shutil.copyfile(src, staged)
                    else:
                        staged.write_text(str(text))
                    os.replace(staged, dst)
            except (OSError, subprocess.CalledProcessError):
                return None
    return target
