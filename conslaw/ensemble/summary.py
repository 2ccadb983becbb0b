"""The summary figures and maps an ensemble keeps of each member (docs/ensembles.md, "What a
member keeps").

1D (a model with a depth): the margins and the centre of mass of the deposit at the end, the
run-out length, drop and travel angle from the top of the release along the chute (Heim's
Fahrböschung, ``alpha = atan(drop / length)``; Lied & Bakkehøi 1980), the largest speed at the
output times, whether every momentum is exactly 0 at the end. 2D: the hazard summary of a run
on terrain (:func:`conslaw.terrain.hazard_maps.hazard_maps`), the deposit's centre and the
peak depth and speed tracked at every step pair. Every member: the relative change of the total
depth (or of the first variable), its steps and solve time. A figure without a value for the
member's model is NaN.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from conslaw.grid2d import Grid2D
from conslaw.peak_fields import REACHED_DEPTH

Array = NDArray[np.float64]

#: Summary figures of a 1D member: name -> (long name, units; "length" = the scene's unit).
SUMMARY_1D = {
    "front": ("leading margin at the end (where h falls below the covered depth)", "length"),
    "rear": ("trailing margin at the end (where h rises above the covered depth)", "length"),
    "deposit_centre": ("centre of mass at the end, along x", "length"),
    "runout_length": ("horizontal distance from the top of the release to the front", "length"),
    "drop": ("elevation of the top of the release above the front", "length"),
    "travel_angle": ("travel angle atan(drop / runout_length)", "degree"),
    "max_speed": ("largest speed of a covered cell at the output times", "speed"),
    "mass_drift": ("relative change of the total of the first variable", "1"),
    "at_rest": ("1 if every momentum is exactly 0 at the end, else 0", "1"),
    "at_boundary": ("1 if the flow covered an end cell bare at t = 0 (run-out cut short)", "1"),
    "steps": ("time steps", "1"),
    "solve_seconds": ("wall time of the time loop", "s"),
}
#: Summary figures of a 2D member.
SUMMARY_2D = {
    "runout_length": ("horizontal distance from the top of the release to the run-out end", "m"),
    "drop": ("elevation of the top of the release above the run-out end", "m"),
    "travel_angle": ("travel angle atan(drop / runout_length)", "degree"),
    "deposit_x": ("centre of mass at the end, x", "length"),
    "deposit_y": ("centre of mass at the end, y", "length"),
    "max_depth": ("largest flow depth of any cell at any step", "length"),
    "max_speed": ("largest speed of any cell at any step", "speed"),
    "mass_drift": ("relative change of the total of the first variable", "1"),
    "at_rest": ("1 if every momentum is exactly 0 at the end, else 0", "1"),
    "at_boundary": ("1 if the flow reached a side cell at some step (run-out cut short)", "1"),
    "steps": ("time steps", "1"),
    "solve_seconds": ("wall time of the time loop", "s"),
}
#: Maps kept on request: name -> long name, by dimension.
FIELD_NAMES = {
    1: {
        "max_depth": "largest depth at the output times",
        "final_depth": "depth at the end",
    },
    2: {
        "peak_depth": "largest flow depth at any step",
        "peak_speed": "largest speed at any step",
        "peak_pressure": "largest pressure rho |U|^2 at any step (kPa; models with a density)",
        "deposit": "flow depth at the end",
    },
}
#: Points along the chute from the top of the release to the front at which its elevation
#: profile is evaluated (each integrated on 20 sub-steps): the run-out to about 1e-7 of itself.
PATH_POINTS = 1001
#: The default covered depth, relative to the largest initial depth.
RELATIVE_THRESHOLD = 1e-3


def _nan_summary(names: dict[str, Any]) -> dict[str, float]:
    return dict.fromkeys(names, math.nan)


def _at_rest(model: Any, q: Array) -> float:
    rows = [index for index in (model.momentum_index, model.momentum_y_index) if index is not None]
    if not rows:
        return math.nan
    return float(all(not np.any(q[row]) for row in rows))


def member_summary(result: Any, depth_threshold: float | None = None) -> dict[str, float]:
    """The summary figures of a finished run (:data:`SUMMARY_1D` or :data:`SUMMARY_2D`).

    Parameters
    ----------
    result : RunResult or RunResult2D
    depth_threshold : float, optional
        1D: depth above which a cell counts as covered (default :data:`RELATIVE_THRESHOLD`
        times the largest initial depth). 2D runs on terrain use the hazard maps' reached
        depth.

    Returns
    -------
    dict of str to float
    """
    if isinstance(result.grid, Grid2D):
        return _summary_2d(result)
    return _summary_1d(result, depth_threshold)


def _summary_1d(result: Any, depth_threshold: float | None) -> dict[str, float]:
    model, grid = result.model, result.grid
    summary = _nan_summary(SUMMARY_1D)
    final = result.states[-1]
    summary["mass_drift"] = float(result.mass_drift[0])
    summary["steps"] = float(result.steps)
    summary["solve_seconds"] = float(result.solve_seconds)
    summary["at_rest"] = _at_rest(model, final.q)
    depth_row = model.depth_index
    if depth_row is None:
        return summary
    x = grid.centres()
    h0 = result.initial.q[depth_row]
    threshold = depth_threshold
    if threshold is None:
        threshold = RELATIVE_THRESHOLD * float(np.max(h0)) if np.max(h0) > 0 else 0.0
    h = final.q[depth_row]
    covered, released = h > threshold, h0 > threshold
    speeds = [np.abs(model.primitive_fields(s.q)["u"])[s.q[depth_row] > threshold]
              for s in result.states]  # fmt: skip
    summary["max_speed"] = float(max((s.max() for s in speeds if s.size), default=math.nan))
    # An end cell reached by the flow (one covered from the start, a release or reservoir
    # against the boundary, does not count).
    start_ends = h0[[0, -1]] > threshold
    ends = [state.q[depth_row][[0, -1]] > threshold for state in result.states]
    summary["at_boundary"] = float(any(np.any(end & ~start_ends) for end in ends))
    if np.sum(h) > 0:
        summary["deposit_centre"] = float(np.sum(h * x) / np.sum(h))
    if not covered.any() or not released.any():
        return summary
    front, rear = margins(x, h, threshold)
    top = margins(x, h0, threshold)[1]
    summary.update(front=front, rear=rear, runout_length=front - top)
    chute = getattr(model, "chute", None)
    if chute is not None:
        # The profile is integrated on 20 points per point asked for: ask for a fine path.
        horizontal, elevation = chute.elevation_profile(np.linspace(top, front, PATH_POINTS))
        length = float(horizontal[-1] - horizontal[0])
        drop = float(elevation[0] - elevation[-1])
        summary.update(runout_length=length, drop=drop)
        summary["travel_angle"] = math.degrees(math.atan2(drop, length))
    return summary


def margins(x: Array, h: Array, threshold: float) -> tuple[float, float]:
    """The outermost crossings of ``h = threshold``: (front, rear), each between the outermost
    covered cell centre and its uncovered neighbour, by linear interpolation (a continuous
    function of the run's parameters, unlike a cell centre); at an end of the domain, the end
    cell's centre."""
    covered = np.flatnonzero(h > threshold)
    last, first = int(covered[-1]), int(covered[0])
    front, rear = float(x[last]), float(x[first])
    if last + 1 < h.size:
        front += (h[last] - threshold) / (h[last] - h[last + 1]) * (x[last + 1] - x[last])
    if first > 0:
        rear -= (h[first] - threshold) / (h[first] - h[first - 1]) * (x[first] - x[first - 1])
    return float(front), float(rear)


def _summary_2d(result: Any) -> dict[str, float]:
    model, grid = result.model, result.grid
    summary = _nan_summary(SUMMARY_2D)
    final = result.final
    summary["mass_drift"] = float(result.mass_drift[0])
    summary["steps"] = float(result.steps)
    summary["solve_seconds"] = float(result.solve_seconds)
    summary["at_rest"] = _at_rest(model, final.q)
    if result.peaks is not None:
        depth = result.peaks.depth
        summary["max_depth"] = float(np.max(depth))
        summary["max_speed"] = float(np.max(result.peaks.speed))
        layer = float(np.min(depth))  # a thin layer everywhere is not flow reaching a side
        sides = np.concatenate([depth[0], depth[-1], depth[:, 0], depth[:, -1]])
        summary["at_boundary"] = float(np.any(sides >= layer + REACHED_DEPTH))
    depth_row = model.depth_index
    if depth_row is not None and np.sum(final.q[depth_row]) > 0:
        x, y = grid.centres()
        weight = final.q[depth_row] / np.sum(final.q[depth_row])
        summary["deposit_x"] = float(np.sum(weight.sum(axis=0) * x))
        summary["deposit_y"] = float(np.sum(weight.sum(axis=1) * y))
    from conslaw.terrain.hazard_maps import hazard_maps

    maps = hazard_maps(result)
    if maps is not None:
        for name, key in (
            ("runout_length", "runout_length_m"),
            ("drop", "drop_m"),
            ("travel_angle", "travel_angle_deg"),
        ):
            value = maps.summary[key]
            summary[name] = math.nan if value is None else float(value)
    return summary


def member_fields(result: Any) -> dict[str, Array]:
    """The maps of a finished run (:data:`FIELD_NAMES`; empty for a model without a depth).

    Parameters
    ----------
    result : RunResult or RunResult2D

    Returns
    -------
    dict of str to ndarray
        1D: ``(nx,)`` arrays; 2D: ``(ny, nx)``; the cell centres as ``_x`` (and ``_y``).
    """
    depth_row = result.model.depth_index
    if depth_row is None:
        return {}
    final = result.states[-1].q[depth_row]
    if isinstance(result.grid, Grid2D):
        if result.peaks is None:
            return {}
        x, y = result.grid.centres()
        maps = {
            "_x": np.asarray(x),
            "_y": np.asarray(y),
            "peak_depth": np.array(result.peaks.depth),
            "peak_speed": np.array(result.peaks.speed),
            "deposit": np.array(final),
        }
        density = getattr(result.model.params, "density", None)
        if density is not None:
            maps["peak_pressure"] = np.array(result.peaks.pressure(density))
        return maps
    depths = np.stack([state.q[depth_row] for state in result.states])
    return {
        "_x": np.asarray(result.grid.centres()),
        "max_depth": depths.max(axis=0),
        "final_depth": np.array(final),
    }
