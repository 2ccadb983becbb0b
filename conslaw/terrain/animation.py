"""An animated GIF of the flow depth of a run on terrain, one frame per output time, over the
hillshade of its terrain (docs/output.md, "Hazard maps"): ``output.formats = [..., "gif"]``."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from PIL import Image

from conslaw.peak_fields import REACHED_DEPTH
from conslaw.terrain.hazard_figure import hazard_map_figure

#: Time each frame is shown, ms.
FRAME_MILLISECONDS = 500


def flow_depth_gif(result: Any, dem: Any, released: np.ndarray) -> bytes:
    """The GIF bytes: the flow depth normal to the slope where it is at least
    :data:`~conslaw.peak_fields.REACHED_DEPTH`, at the start and at every output time, on one
    colour scale (0 to the largest peak depth), looping.

    Parameters
    ----------
    result : RunResult2D
        A run whose model gives a flow depth (``flow_depth_and_speed``) and whose ``peaks``
        are set.
    dem : DigitalElevationModel
        The terrain on the run's cells.
    released : numpy.ndarray of bool
        The released cells, outlined on every frame.

    Returns
    -------
    bytes
    """
    peaks = result.peaks
    top = max(float(np.max(peaks.depth)), REACHED_DEPTH)
    frames = []
    for state in (result.initial, *result.states):
        fields = result.model.flow_depth_and_speed(state.q, peaks.aux)
        depth = np.where(fields[0] >= REACHED_DEPTH, fields[0], 0.0)
        figure = hazard_map_figure(
            dem, depth, label="flow depth (m)", release_mask=released, threshold=0.0
        )
        axes = figure.axes[0]
        axes.images[-1].set_clim(0.0, top)
        axes.set_title(f"{result.scene.name}: t = {state.t:g} s", fontsize="medium")
        canvas = FigureCanvasAgg(figure)
        canvas.draw()
        frames.append(Image.fromarray(np.asarray(canvas.buffer_rgba())).convert("RGB"))
    buffer = io.BytesIO()
    frames[0].save(
        buffer,
        format="GIF",
        save_all=True,
        append_images=frames[1:],
        duration=FRAME_MILLISECONDS,
        loop=0,
    )
    return buffer.getvalue()
