"""The gait search's progress label: how far, of about how many, and the time left."""

from scalf_opt.optimize.gait_search import search_progress


def test_the_label_counts_against_the_usual_and_estimates_from_the_pace():
    assert search_progress(3, start=0.0, now=2.0, usual=100) == "gait 3 of about 100"
    # 10 gaits in 8 s since the first: 8/9 s each, 91 to go (this one included)
    assert search_progress(10, 0.0, 8.0, 100) == "gait 10 of about 100, about 81 s left"
    assert search_progress(10, 0.0, 90.0, 100) == "gait 10 of about 100, about 15 min left"
    assert search_progress(101, 0.0, 90.0, 100) == "gait 101 (more than the usual 100)"
