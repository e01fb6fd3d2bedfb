"""One set of OpenBLAS kernels on every x86-64 CPU: the rule, and that it took effect here."""

import ctypes
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import scalf_opt  # noqa: F401 (its import pins the kernels)
from scalf_opt.blas_kernels import (
    PINNED_CORE,
    cpu_flags,
    kernel_mismatch,
    loaded_kernels,
    pin_blas_kernels,
    single_blas_thread,
)

X86 = frozenset({"avx2", "fma", "sse2"})


def test_the_rule():
    env: dict[str, str] = {}
    assert pin_blas_kernels(env, "x86_64", X86) == PINNED_CORE == env["OPENBLAS_CORETYPE"]
    user = {"OPENBLAS_CORETYPE": "Zen"}
    assert pin_blas_kernels(user, "x86_64", X86) == "Zen" and user["OPENBLAS_CORETYPE"] == "Zen"
    for machine, flags in (
        ("x86_64", frozenset({"avx", "sse2"})),
        ("arm64", X86),
        ("x86_64", frozenset()),
    ):
        env = {}
        assert pin_blas_kernels(env, machine, flags) is None and env == {}


def test_cpu_flags_are_read_and_a_missing_file_is_none(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nflags\t\t: fpu avx2 fma\nbugs\t\t: none\n")
    assert cpu_flags(info) == {"fpu", "avx2", "fma"}
    assert cpu_flags(tmp_path / "missing") == frozenset()


def _loaded_core() -> str:
    libs = sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("libscipy_openblas*.so"))
    if not libs:
        pytest.skip("numpy is not linked against scipy-openblas here")
    library = ctypes.CDLL(str(libs[0]))  # already loaded by numpy: the same handle
    corename = getattr(library, "scipy_openblas_get_corename64_", None)
    if corename is None:
        pytest.skip("this OpenBLAS does not name its kernels")
    corename.restype = ctypes.c_char_p
    return corename().decode()


needs_avx2 = pytest.mark.skipif(
    pin_blas_kernels({}) is None,  # the rule itself, on this machine, in an empty environment
    reason="the kernels are pinned on x86-64 CPUs with AVX2 and FMA",
)


@needs_avx2
def test_numpy_runs_the_pinned_kernels_in_the_tests():
    assert _loaded_core() == PINNED_CORE


def _set_by_the_command_line(variable: str) -> str | None:
    """``variable`` as ``scalf-opt --version`` leaves it, started without it in its environment."""
    probe = (
        "import runpy, sys; sys.argv = ['scalf-opt', '--version']\n"
        "try:\n    runpy.run_module('scalf_opt', run_name='__main__')\n"
        "except SystemExit:\n    pass\n"
        f"import numpy, os; print(os.environ.get({variable!r}))"
    )
    env = {k: v for k, v in os.environ.items() if k != variable}
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1]


@needs_avx2
def test_numpy_runs_the_pinned_kernels_in_the_command_line():
    assert _set_by_the_command_line("OPENBLAS_CORETYPE") == PINNED_CORE


def test_blas_runs_on_one_thread_unless_the_user_chose():
    env: dict[str, str] = {}
    assert single_blas_thread(env) == "1" == env["OPENBLAS_NUM_THREADS"]
    user = {"OPENBLAS_NUM_THREADS": "4"}
    assert single_blas_thread(user) == "4" == user["OPENBLAS_NUM_THREADS"]


def test_the_command_line_runs_blas_on_one_thread():
    assert _set_by_the_command_line("OPENBLAS_NUM_THREADS") == "1"


def test_a_mismatch_is_named_with_its_fix():
    message = kernel_mismatch("Haswell", {"libscipy_openblas64_.so": "SkylakeX"})
    assert message is not None
    assert "libscipy_openblas64_.so" in message and "SkylakeX" in message
    assert "OPENBLAS_CORETYPE=Haswell" in message and "\n" not in message
    assert kernel_mismatch("Haswell", {"a.so": "HASWELL"}) is None  # OpenBLAS's own spelling
    assert kernel_mismatch(None, {"a.so": "SkylakeX"}) is None  # nothing was pinned
    assert kernel_mismatch("Haswell", {}) is None


def test_the_loaded_kernels_are_read_from_the_process(tmp_path):
    assert loaded_kernels(tmp_path / "missing") == {}
    found = loaded_kernels()
    if not found:
        pytest.skip("no OpenBLAS that names its kernels is mapped here")
    assert any(name.startswith("libscipy_openblas") for name in found)


def _import_warnings(code: str, core: str) -> str:
    """stderr of ``code``, run after numpy has loaded OpenBLAS on ``core``'s kernels."""
    probe = (
        f"import os; os.environ['OPENBLAS_CORETYPE'] = {core!r}\n"
        "import numpy\n"
        "del os.environ['OPENBLAS_CORETYPE']\n" + code
    )
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    return out.stderr


@needs_avx2
def test_numpy_loaded_first_on_other_kernels_is_warned_about():
    # Sandybridge (AVX) runs on every CPU the pin applies to; numpy keeps it, the pin comes late
    stderr = _import_warnings("import scalf_opt", "Sandybridge")
    if not loaded_kernels():
        pytest.skip("this OpenBLAS does not name its kernels")
    assert "RuntimeWarning" in stderr and "Sandybridge kernels, not Haswell" in stderr
    assert "Import scalf_opt before numpy" in stderr
    assert _import_warnings("import scalf_opt", PINNED_CORE) == ""  # the same kernels: silent
