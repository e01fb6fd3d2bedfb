"""A headless Chromium that hangs: stopped after its timeout, its screenshot kept when it had
written it (and said so), else run again in a fresh profile (ATTEMPTS runs in all), else a
one-line error.

Chromium is replaced by a script (``SCALF_OPT_CHROMIUM``), so these run without it; the hang is
real (measured: 1 to 3 in 60 renders when two run at once, both at exit)."""

import stat
import time

import pytest

from scalf_opt.errors import ConfigError
from scalf_opt.viz.browser import ATTEMPTS, render_page

HANGS_AFTER_THE_SCREENSHOT = """#!/bin/sh
for arg in "$@"; do case "$arg" in --screenshot=*) shot="${arg#--screenshot=}";; esac; done
printf 'PNG' > "$shot"
echo '[1:1:1202/001853.731463:INFO:CONSOLE:1] "Uncaught Error: bad", source: page.html (1)' >&2
echo "3 bytes written to file $shot" >&2
exec sleep 60
"""

HANGS_EVERY_TIME = """#!/bin/sh
echo "$@" >> "$0.calls"
exec sleep 60
"""


def fake_chromium(tmp_path, monkeypatch, script):
    path = tmp_path / "chromium"
    path.write_text(script)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("SCALF_OPT_CHROMIUM", str(path))
    page = tmp_path / "page.html"
    page.write_text("<html><head></head><body></body></html>")
    return path, page


def test_a_chromium_that_hangs_after_its_screenshot_gives_the_screenshot(tmp_path, monkeypatch):
    _, page = fake_chromium(tmp_path, monkeypatch, HANGS_AFTER_THE_SCREENSHOT)
    start = time.perf_counter()
    rendering = render_page(page, tmp_path / "shot.png", timeout_s=1.0)
    assert time.perf_counter() - start < 30  # stopped, not waited for
    assert (tmp_path / "shot.png").read_bytes() == b"PNG"
    assert rendering.errors == ["Uncaught Error: bad"]  # what it logged until stopped


def test_a_chromium_that_always_hangs_is_run_attempts_times_then_refused(tmp_path, monkeypatch):
    _, page = fake_chromium(tmp_path, monkeypatch, HANGS_EVERY_TIME)
    with pytest.raises(ConfigError, match=f"did not finish within 1 s \\({ATTEMPTS} attempts\\)"):
        render_page(page, tmp_path / "shot.png", timeout_s=1.0)
    assert len((tmp_path / "chromium.calls").read_text().splitlines()) == ATTEMPTS
    assert not (tmp_path / "shot.png").exists()
