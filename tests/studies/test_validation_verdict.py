"""The sentence under `paper`'s validation table: agree, disagree, or not compared."""

from types import SimpleNamespace

from scalf_opt.studies.paper import ipopt_above_pattern_search, unvalidated
from scalf_opt.studies.paper_report import validation_verdict


def reproduction(fine_j: dict[str, float], ipopt_j: dict[str, float], solved: bool = True):
    """A stand-in with what the validation reads: each leg's fine pattern search and Ipopt."""

    def optimum(energy_j: float, success: bool = True) -> SimpleNamespace:
        return SimpleNamespace(swing_energy_j=energy_j, success=success)

    return SimpleNamespace(
        optima={
            "pattern_fine": {leg: optimum(e) for leg, e in fine_j.items()},
            "ipopt": {leg: optimum(e, solved or leg != "LH") for leg, e in ipopt_j.items()},
        }
    )


def test_the_verdict_says_whether_the_pattern_search_beat_ipopt():
    agree = reproduction({"RF": 25.047, "LH": 24.808}, {"RF": 25.047, "LH": 24.810})
    assert ipopt_above_pattern_search(agree) == {} and unvalidated(agree) == []
    assert validation_verdict(agree).startswith("They agree")
    # Solo12 before the condensed NLP was normalized: Ipopt's 179 J against the search's 0.158 J
    solo = reproduction({"RF": 0.158, "LH": 0.210}, {"RF": 179.05, "LH": 0.2101})
    assert list(ipopt_above_pattern_search(solo)) == ["RF"]
    assert validation_verdict(solo).startswith("**They disagree**")
    assert "RF 99.91 % below" in validation_verdict(solo)


def test_a_leg_ipopt_did_not_solve_is_not_compared():
    failed = reproduction({"RF": 25.047, "LH": 24.808}, {"RF": 25.047, "LH": float("inf")}, False)
    assert unvalidated(failed) == ["LH"] and ipopt_above_pattern_search(failed) == {}
    assert validation_verdict(failed).startswith("**Not compared** on LH")
