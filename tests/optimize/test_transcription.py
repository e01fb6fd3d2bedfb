"""The transcription apart from the problem: its rate, refinement, check grid and scheme."""

import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.sampling import (
    CHECK_FACTOR,
    MAX_RATE_HZ,
    Transcription,
    initial_rate_hz,
    scheme,
)


def test_refinement_doubles_and_stops_below_the_finest_rate():
    t = Transcription(300.0)
    assert t.refined().rate_hz == 600.0 and t.refined(3).rate_hz == 900.0
    assert not t.finest and Transcription(MAX_RATE_HZ / 2 + 1).finest


def test_the_first_rate_is_the_familys_and_the_check_ten_times_it():
    gait = Gait()
    family = make_family("joint-6")
    first = Transcription.first(gait, family)
    assert first.rate_hz == initial_rate_hz(gait, family) > gait.sample_rate_hz
    assert first.check(gait).rate_hz == pytest.approx(CHECK_FACTOR * first.rate_hz, rel=1e-12)


def test_on_samples_the_same_physics_at_its_rate(scalf):
    pipeline = EnergyPipeline(scalf, Gait(), loads="trunk")
    fine = Transcription(400.0).on(pipeline)
    assert fine.gait.sample_rate_hz == 400.0 and pipeline.gait.sample_rate_hz == 200.0
    assert fine.robot_physics is pipeline.robot_physics  # the robot's compiled physics is shared
    assert Transcription.of(fine) == Transcription(400.0)


def test_small_families_are_condensed_larger_ones_lifted():
    assert scheme(make_family("paper").n_params) == "condensed"
    assert scheme(make_family("joint-2").n_params) == "condensed"
    assert scheme(make_family("joint-3").n_params) == "lifted"
