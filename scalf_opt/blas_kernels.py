"""The same numbers on every x86-64 machine: one set of OpenBLAS kernels, chosen before numpy loads.

numpy's OpenBLAS picks its kernels by CPU at load time (``DYNAMIC_ARCH``): an Intel CPU with
AVX-512 gets the ``SkylakeX`` kernels, an AMD one the ``Haswell`` ones. They sum in another
order, so a matrix product differs in its last bits, and a flat optimum (a swing whose energy
hardly moves along a valley) ends a few iterations elsewhere: the same command printed a swing
energy of 0.6320 J on one machine and 0.6303 J on another. OpenBLAS reads the kernel to use from
``OPENBLAS_CORETYPE`` when it loads, so :func:`pin_blas_kernels` sets it to ``Haswell`` (AVX2
and FMA, which every x86-64 CPU of the last decade has, and the kernels OpenBLAS itself picks
for AMD's) before anything imports numpy. A value the user has set is kept; a CPU without
AVX2 or FMA keeps OpenBLAS's own choice (forcing kernels it cannot run would crash).

The same module runs OpenBLAS on one thread (:func:`single_blas_thread`), numpy's and the one
CasADi's MUMPS factorizes with: Ipopt's interface to MUMPS holds one lock for the whole process, so
a second BLAS thread could only help the factorization itself, whose fronts here are too small to
split; its idle threads instead spun in ``sched_yield`` (650,000 calls and 11 s of system time in
one free-trajectory bound of 18 s), taking the second core from the other leg's solve or the
other study worker. One thread also makes the numbers independent of the machine's core
count: on two threads a product is split differently and can differ in its last bit (the
tutorial's symmetry check printed 0.0e+00 on two threads and 2.0e-16 on one; every other
documented output was the same).

A program that imports numpy or SciPy before ``scalf_opt`` has loaded OpenBLAS with its own
kernels already, and they cannot be changed afterwards: :func:`warn_if_kernels_differ` then warns
once (on an AVX-512 machine the free-trajectory bound's levels took another round-off path and
stopped one level later, 0.7 % lower), naming the fix.

This module imports nothing but the standard library: it must run before numpy is imported.
"""

from __future__ import annotations

import ctypes
import os
import platform
import warnings
from collections.abc import Mapping, MutableMapping
from pathlib import Path

PINNED_CORE = "Haswell"
"""OpenBLAS kernels used on every x86-64 CPU that can run them (AVX2 and FMA)."""

_NEEDED_FLAGS = frozenset({"avx2", "fma"})


def cpu_flags(cpuinfo: Path = Path("/proc/cpuinfo")) -> frozenset[str]:
    """The instruction-set flags of the first CPU in ``cpuinfo``; empty where it cannot be read."""
    try:
        with cpuinfo.open(encoding="ascii", errors="replace") as lines:
            for line in lines:
                if line.startswith("flags"):
                    return frozenset(line.partition(":")[2].split())
    except OSError:
        pass
    return frozenset()


def pin_blas_kernels(
    environ: MutableMapping[str, str] = os.environ,
    machine: str | None = None,
    flags: frozenset[str] | None = None,
) -> str | None:
    """Set ``OPENBLAS_CORETYPE`` to :data:`PINNED_CORE` where it is safe; return what it is now.

    Args:
        environ: The environment to set it in (the process's).
        machine: The CPU architecture (default ``platform.machine()``).
        flags: The CPU's flags (default: read from ``/proc/cpuinfo``).

    Returns:
        The kernels OpenBLAS will be asked for, or ``None`` where it keeps its own choice (not
        x86-64, no AVX2/FMA, or flags unreadable, as on macOS).
    """
    if environ.get("OPENBLAS_CORETYPE"):
        return environ["OPENBLAS_CORETYPE"]
    if (machine or platform.machine()).lower() not in ("x86_64", "amd64"):
        return None
    if not _NEEDED_FLAGS.issubset(cpu_flags() if flags is None else flags):
        return None
    environ["OPENBLAS_CORETYPE"] = PINNED_CORE
    return PINNED_CORE


def single_blas_thread(environ: MutableMapping[str, str] = os.environ) -> str:
    """Set ``OPENBLAS_NUM_THREADS`` to 1 unless the user set it; return what it is now."""
    if not environ.get("OPENBLAS_NUM_THREADS"):
        environ["OPENBLAS_NUM_THREADS"] = "1"
    return environ["OPENBLAS_NUM_THREADS"]


def loaded_kernels(maps: Path = Path("/proc/self/maps")) -> dict[str, str]:
    """The kernels of every OpenBLAS loaded in this process: ``{library file name: core}``.

    Read from the libraries' own ``*_get_corename*`` (numpy's and SciPy's scipy-openblas have
    it); empty where the process's mappings cannot be read (not Linux) or none names its core.
    """
    try:
        paths = sorted(
            {line.split()[-1] for line in maps.read_text().splitlines() if "openblas" in line}
        )
    except OSError:
        return {}
    found: dict[str, str] = {}
    for path in paths:
        try:
            library = ctypes.CDLL(path)  # already loaded: the same handle, nothing runs
        except OSError:
            continue
        for symbol in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename"):
            corename = getattr(library, symbol, None)
            if corename is not None:
                corename.restype = ctypes.c_char_p
                found[Path(path).name] = corename().decode()
                break
    return found


def kernel_mismatch(pinned: str | None, loaded: Mapping[str, str]) -> str | None:
    """Why results may differ from the command line's, or ``None`` when the kernels agree.

    Args:
        pinned: The kernels asked for (:func:`pin_blas_kernels`); ``None``: none asked.
        loaded: The kernels in use (:func:`loaded_kernels`).
    """
    if pinned is None:
        return None
    other = {lib: core for lib, core in loaded.items() if core.lower() != pinned.lower()}
    if not other:
        return None
    lib, core = sorted(other.items())[0]
    return (
        f"OpenBLAS ({lib}) was loaded before scalf_opt and runs its {core} kernels, not "
        f"{pinned}: numbers can differ from the command line's in their last digits, and a flat "
        "optimum can end elsewhere. Import scalf_opt before numpy and SciPy, or set "
        f"OPENBLAS_CORETYPE={pinned} before Python starts."
    )


def warn_if_kernels_differ(pinned: str | None) -> None:
    """Warn if an OpenBLAS loaded earlier runs other kernels than ``pinned``."""
    message = kernel_mismatch(pinned, loaded_kernels())
    if message is not None:
        warnings.warn(message, RuntimeWarning, stacklevel=3)
