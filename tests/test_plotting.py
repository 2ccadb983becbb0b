"""The figures of a run say what they show: axis labels with the model's long names and scales,
one legend entry per output time, the chute at equal aspect, a curved transition shaded, no
velocity drawn in the thin film behind a flow, and whether an exact solution is drawn."""

from __future__ import annotations

import math

import numpy as np
import pytest

import conslaw
from conslaw.plotting import FILM_FRACTION, _display_rows, profiles_figure
from conslaw.result import RunResult
from conslaw_models.chute_figure import chute_figure


@pytest.fixture(scope="module")
def runout() -> RunResult:
    return conslaw.run("sh-runout-shock", n_cells=120)


def test_profile_axes_name_their_quantities_and_scales(runout: RunResult) -> None:
    figure = profiles_figure(runout)
    depth, velocity = figure.axes
    assert "depth normal to the bed / H" in depth.get_ylabel()
    assert "depth-averaged velocity / (g L)^(1/2)" in velocity.get_ylabel()
    assert velocity.get_xlabel() == "x: arc length along the bed / L (dimensionless)"
    labels = [text.get_text() for text in depth.get_legend().get_texts()]
    assert labels == [f"t = {t:g}" for t in (0, 4, 8, 12, 16, 20)]
    title = depth.get_title()
    assert "nessyahu-tadmor" in title and "no exact solution for this scene" in title


def test_successive_output_times_get_colours_apart(runout: RunResult) -> None:
    lines = profiles_figure(runout).axes[0].get_lines()
    colours = np.array([line.get_color() for line in lines])[:, :3]
    # Neighbouring times differ by at least a tenth of the colour cube's diagonal.
    assert np.linalg.norm(np.diff(colours, axis=0), axis=1).min() > 0.1 * math.sqrt(3)


def test_the_curved_transition_is_shaded_on_every_axis(runout: RunResult) -> None:
    figure = profiles_figure(runout)
    for axis in figure.axes:
        spans = [patch.get_x() for patch in axis.patches]
        assert spans == [pytest.approx(21.5)]
    assert "curved transition" in [text.get_text() for text in figure.axes[0].texts]


def test_the_velocity_of_the_thin_film_is_not_drawn(runout: RunResult) -> None:
    q = runout.final.q
    (_, depth), (_, velocity) = _display_rows(runout.model, q, FILM_FRACTION)
    film = (depth > 0) & (depth < FILM_FRACTION * depth.max())
    body = depth >= FILM_FRACTION * depth.max()
    assert np.all(np.isnan(velocity[film]))
    assert np.all(np.isfinite(velocity[body]))


def test_the_chute_is_drawn_at_equal_aspect_in_a_grid_of_panels(runout: RunResult) -> None:
    figure = chute_figure(runout)
    shown = [axis for axis in figure.axes if axis.get_visible()]
    assert len(shown) == 6
    for axis in shown:
        assert axis.get_aspect() == 1.0
    # Three columns: the panels of one row share a y position.
    assert len({round(axis.get_position().y0, 3) for axis in shown}) == 2
    assert "equal scales" in figure.get_suptitle()


def test_a_scene_with_an_exact_solution_says_so_in_the_title() -> None:
    result = conslaw.run("dam-break-wet", n_cells=100)
    title = profiles_figure(result).axes[0].get_title()
    assert "L1(h) at t = 2: " in title and "no exact solution" not in title
    assert profiles_figure(result).axes[0].get_ylabel() == "h\ndepth"


def test_the_depth_is_drawn_along_the_bed_normal_in_units_of_length() -> None:
    """On a 40-degree plane with epsilon = 0.2, the drawn layer's top lies 3 epsilon h from the
    bed along (sin zeta, cos zeta), perpendicular to the bed (it was drawn tilted by 2 zeta)."""
    result = conslaw.run("sh-similarity", n_cells=60, t_end=0.5, parameters__epsilon=0.2)
    figure = chute_figure(result)
    outline = figure.axes[0].patches[0].get_xy()
    n = result.grid.n_cells
    bed, top = outline[:n], outline[n : 2 * n][::-1]
    zeta = np.radians(40.0)
    offset = top - bed
    np.testing.assert_allclose(offset @ np.array([np.cos(zeta), -np.sin(zeta)]), 0.0, atol=1e-12)
    depth = result.final.q[0]
    np.testing.assert_allclose(np.hypot(*offset.T), 3.0 * 0.2 * depth, rtol=1e-12, atol=1e-14)


def test_a_figure_says_which_output_times_it_leaves_out_and_draws_the_start() -> None:
    many = conslaw.run("burgers-sine", n_cells=40, output_interval=0.025)
    assert "6 of 11 output times drawn" in profiles_figure(many).axes[0].get_title()
    single = conslaw.run("burgers-sine", n_cells=40)
    labels = [t.get_text() for t in profiles_figure(single).axes[0].get_legend().get_texts()]
    assert labels[0] == "t = 0 (initial)"
