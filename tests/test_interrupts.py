"""Signals held back across native imports: noted inside the block, delivered once it ends."""

import signal
import subprocess
import sys

import pytest

from scalf_opt.interrupts import Interrupted, signals_held, stop_on_signals


def test_a_held_signal_takes_effect_once_the_block_ends():
    after_the_signal = False
    with stop_on_signals():
        handler = signal.getsignal(signal.SIGINT)
        with pytest.raises(Interrupted), signals_held():
            signal.raise_signal(signal.SIGINT)
            after_the_signal = True  # not interrupted inside the block
        assert signal.getsignal(signal.SIGINT) is handler
    assert after_the_signal


def test_no_signal_no_effect():
    with signals_held():
        pass  # nothing raised on the way out


# Ctrl-C as trimesh (which yourdfpy imports) begins to import its boolean module, which loads
# manifold3d (trimesh's `easy` extra, which yourdfpy requires): a native extension that aborted
# or crashed the interpreter when the signal's exception was raised while it loaded. The signal
# is held: the import ends whole, then the interruption is raised.
_IN_THE_IMPORT = """
import importlib.abc, signal, sys

signal.signal(signal.SIGINT, signal.default_int_handler)  # a background job inherits SIG_IGN

class Interrupt(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "trimesh.boolean":
            signal.raise_signal(signal.SIGINT)
        return None

sys.meta_path.insert(0, Interrupt())
from scalf_opt.robots.loading import load_robot
from scalf_opt.robots.variants import VariantScales, variant_xml

try:
    variant_xml(load_robot("scalf"), VariantScales(thigh_length_scale=1.1))
except KeyboardInterrupt:
    print("interrupted after", "yourdfpy" in sys.modules and "trimesh.boolean" in sys.modules)
"""


def test_ctrl_c_while_a_variant_imports_its_urdf_parser_waits_for_the_import():
    done = subprocess.run(
        [sys.executable, "-c", _IN_THE_IMPORT], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "interrupted after True"
