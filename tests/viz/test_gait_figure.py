"""The cost-of-transport figure of ``scalf-opt gait``: three lines against speed, a failed speed
marked on the axis, and every lower panel a gait field with its unit."""

import matplotlib.pyplot as plt

from scalf_opt.viz.gait_figure import COT_LINES, PANELS, gait_figure


def row(speed, status="ok", **values):
    base = {
        "speed_m_s": speed,
        "status": status,
        "period_s": 0.5,
        "duty_cycle": 0.5,
        "step_length_m": 0.25 * speed,
        "stance_height_m": 0.75,
        "stance_x_offset_front_m": 0.05,
        "stance_x_offset_hind_m": -0.05,
        "average_power_w": 300.0 * speed,
        "cost_of_transport": 0.1 * speed,
        "default_cost_of_transport": 0.15 * speed,
        "reference_cost_of_transport": 0.2 * speed,
        "pinned_by": "period_s up: period_s above the search box's 0.8819 s",
    }
    return {**base, **values}


def test_the_figure_has_the_three_lines_and_a_panel_per_field():
    rows = [
        row(1.0),
        row(0.5, pinned_by=""),
        row(1.5, status="not solved", cost_of_transport=None),
    ]
    fig = gait_figure(rows, "test")
    top, *panels = fig.axes
    labels = [line.get_label() for line in top.get_lines()]
    for _, label, _, _ in COT_LINES:
        assert label in labels
    cheapest = next(line for line in top.get_lines() if line.get_label() == COT_LINES[0][1])
    assert list(cheapest.get_xdata()) == [0.5, 1.0]  # sorted, the failed speed left out
    failed = next(line for line in top.get_lines() if line.get_label() == "search not solved")
    assert list(failed.get_xdata()) == [1.5]
    assert len(panels) == len(PANELS)
    for ax, (_, ylabel, _) in zip(panels, PANELS, strict=True):
        assert ax.get_ylabel() == ylabel and "[" in ylabel and ax.get_xlabel() == "speed v [m/s]"
    step = panels[2].get_lines()[0]
    assert list(step.get_ydata()) == [125.0, 250.0]  # millimetres
    plt.close(fig)


def test_a_gait_held_by_the_search_box_is_hollow_on_the_cost_line_and_in_every_panel():
    # 1.0 m/s held by the box's longest period; 0.5 m/s by a joint's range, as every gait is by some
    # limit: filled
    rows = [row(1.0), row(0.5, pinned_by="stance_height_m up: RF q_knee: joint range (URDF)")]
    fig = gait_figure(rows, "test")
    for ax in fig.axes:
        hollow = [line for line in ax.get_lines() if line.get_markerfacecolor() == "white"]
        drawn = [line for line in hollow if len(line.get_xdata())]
        assert [list(line.get_xdata()) for line in drawn] == [[1.0]] * len(drawn) and drawn, ax
    plt.close(fig)


def test_the_duty_floor_is_the_models_limit_not_the_boxs():
    from scalf_opt.viz.gait_figure import held_by_the_box

    floor = "duty_cycle down: duty_cycle below the search box's 0.5, a trot's floor"
    edge = "period_s up: period_s above the search box's 0.8819 s"
    assert not held_by_the_box(floor) and held_by_the_box(edge)
    assert held_by_the_box(f"{floor}; {edge}") and not held_by_the_box("")
