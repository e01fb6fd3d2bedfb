"""The compile cache: shared safely by concurrent processes, bounded, cleaned of stale entries."""

import os
import subprocess
import sys
import time

import pytest

from scalf_opt.energy import codegen

# a function no other test compiles, big enough that two compilations overlap in time
SCRIPT = """
import sys, casadi as ca
from scalf_opt.energy.codegen import compile_function
x = ca.SX.sym('x', 8)
y = x
for k in range(60):
    y = ca.sin(y) * ca.cos(y + k) + ca.mtimes(ca.DM.ones(8, 8) / 64, y)
fn = compile_function(ca.Function('shared_toy', [x], [y]))
reference = ca.Function('shared_toy_vm', [x], [y])
value = [0.1 * i for i in range(8)]
assert fn.class_name() == 'External', fn.class_name()
sys.stdout.write(repr([float(v) for v in ca.vertsplit(fn(value))]) + '|')
sys.stdout.write(repr([float(v) for v in ca.vertsplit(reference(value))]))
"""


def _needs_compiler():
    if codegen._compiler() is None:
        pytest.skip("no C compiler: the virtual-machine fallback is covered by the other tests")


def test_two_processes_compiling_the_same_function_share_one_intact_entry(tmp_path):
    _needs_compiler()
    env = {**os.environ, "SCALF_OPT_CACHE": str(tmp_path)}
    procs = [
        subprocess.Popen([sys.executable, "-c", SCRIPT], env=env, stdout=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    outputs = [p.communicate(timeout=300)[0] for p in procs]
    assert [p.returncode for p in procs] == [0, 0]
    compiled = [out.split("|")[0] for out in outputs]
    assert compiled[0] == compiled[1]
    # compiled C and CasADi's virtual machine: the same operations, equal to round-off
    got, want = (eval(part) for part in outputs[0].split("|"))
    assert got == pytest.approx(want, rel=1e-12, abs=1e-14)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert len(names) == 2 and names[0].endswith(".sha256") and names[1].endswith(".so")
    library = tmp_path / names[1]
    assert codegen._is_intact(library)
    # a third process finds it and does not compile again
    before = library.stat().st_ino
    third = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True)
    assert third.returncode == 0 and library.stat().st_ino == before


def _entry(folder, name, size, age_s):
    library = folder / f"{name}.so"
    library.write_bytes(b"\0" * size)
    library.with_suffix(".sha256").write_text("x")
    when = time.time() - age_s
    for path in (library, library.with_suffix(".sha256")):
        os.utime(path, (when, when))
    return library


def test_the_cache_drops_stale_and_least_recently_used_entries(tmp_path, monkeypatch):
    monkeypatch.setenv("SCALF_OPT_CACHE_MAX_MB", "0.35")  # 350 kB
    day = 86400.0
    stale = _entry(tmp_path, "stale", 1000, 40 * day)  # another CasADi's, never used again
    old = _entry(tmp_path, "old", 100_000, 5 * day)
    older = _entry(tmp_path, "older", 100_000, 6 * day)
    recent = _entry(tmp_path, "recent", 100_000, 1 * day)
    in_use = _entry(tmp_path, "in_use", 100_000, 10.0)  # found by another process just now
    kept = _entry(tmp_path, "just_compiled", 100_000, 3 * day)
    leftover = tmp_path / ".killed.so.1234"  # staged by a process killed mid-publish
    leftover.write_bytes(b"partial")
    os.utime(leftover, (time.time() - day, time.time() - day))
    staging = tmp_path / ".busy.so.99"  # being published right now
    staging.write_bytes(b"partial")
    orphan = tmp_path / "orphan.sha256"
    orphan.write_text("x")
    os.utime(orphan, (time.time() - day, time.time() - day))

    removed = set(codegen.prune_cache(tmp_path, keep=kept))

    left = {p.name for p in tmp_path.iterdir()}
    assert stale not in left and {stale, stale.with_suffix(".sha256")} <= removed
    assert leftover in removed and orphan in removed and staging.exists()
    # 500 kB of live entries for a 350 kB bound: the least recently used go until it fits,
    # the one just compiled and the one in use stay whatever their age
    assert {older, old} <= removed
    assert recent.exists() and in_use.exists() and kept.exists()
    size = sum(p.stat().st_size for p in tmp_path.iterdir() if not p.name.startswith("."))
    assert size <= 350_000 + 3 * len("x")


def test_using_an_entry_marks_it_recently_used(tmp_path, monkeypatch):
    _needs_compiler()
    monkeypatch.setenv("SCALF_OPT_CACHE", str(tmp_path))
    import casadi as ca

    x = ca.SX.sym("x")
    fn = ca.Function("lru_toy", [x], [3 * ca.cos(x)])
    library = codegen.compile_library("lru_toy", [fn])
    assert library is not None
    long_ago = time.time() - 10 * 86400.0
    os.utime(library, (long_ago, long_ago))
    assert codegen.compile_library("lru_toy", [fn]) == library
    assert time.time() - library.stat().st_mtime < 60.0


def test_the_bound_is_read_from_the_environment(monkeypatch):
    monkeypatch.setenv("SCALF_OPT_CACHE_MAX_MB", "12.5")
    assert codegen.cache_max_bytes() == 12_500_000
    monkeypatch.delenv("SCALF_OPT_CACHE_MAX_MB")
    assert codegen.cache_max_bytes() == int(codegen.DEFAULT_MAX_MB * 1e6)
