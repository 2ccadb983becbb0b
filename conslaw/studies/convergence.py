"""Convergence and work-precision studies: error against N and against run time.

For every (scheme, reconstructor) and every N the scene is solved ``repeats`` times; the table
holds the steps, the median (min, max) wall time of the solve (set-up, compilation and output
excluded), the errors (docs/equations.md, "Error norms") of variable 0 against the exact cell
averages, and the observed
L1 order between successive N. The first solve of every combination (JIT compilation or loading
the compiled kernels from the cache) is timed on its own and reported apart, as is the time to
import conslaw in a fresh process.
"""

from __future__ import annotations

import csv
import io
import json
import statistics
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from conslaw.analysis import observed_orders
from conslaw.config import (
    Scene,
    is_two_dimensional,
    load_scene,
    read_scene_file,
    scene_path,
    scheme_variants,
)
from conslaw.errors import ConfigError, shown
from conslaw.grid import Grid
from conslaw.grid2d import Grid2D
from conslaw.scene2d import Scene2D, load_scene_2d
from conslaw.simulation import exact_solution_for, simulate
from conslaw.simulation2d import exact_solution_2d, simulate_2d

#: Most solves per N (``--repeats``).
MAX_REPEATS = 1000


@dataclass(frozen=True)
class ConvergenceRow:
    """One solve of the study (times in seconds)."""

    scheme: str
    reconstructor: str
    n_cells: int
    steps: int
    solve_median: float
    solve_min: float
    solve_max: float
    l1: float
    l2: float
    linf: float
    order_l1: float | None
    margin_error: float | None = None
    order_margin: float | None = None


@dataclass
class ConvergenceStudy:
    """All rows of a study, with the one-off costs measured apart."""

    scene: str
    t_end: float
    repeats: int
    rows: list[ConvergenceRow] = field(default_factory=list)
    warmup_seconds: dict[str, float] = field(default_factory=dict)
    import_seconds: float | None = None

    def table(self) -> str:
        """Markdown table of the rows (with the margin error and its order when the margins
        are tracked and the exact solution has margins)."""
        margins = any(r.margin_error is not None for r in self.rows)
        extra = " margin error | order margin |" if margins else ""
        lines = [
            "| scheme | reconstructor | N | steps | solve s (median, min-max) | L1 | L2 | Linf "
            "| order L1 |" + extra,
            "|---|---|---|---|---|---|---|---|---|" + ("---|---|" if margins else ""),
        ]
        for r in self.rows:
            order = _format(r.order_l1, ".2f")
            cells = (
                f" {_format(r.margin_error, '.3e')} | {_format(r.order_margin, '.2f')} |"
                if margins
                else ""
            )
            lines.append(
                f"| {r.scheme} | {r.reconstructor} | {r.n_cells} | {r.steps} | "
                f"{r.solve_median:.4f} ({r.solve_min:.4f}-{r.solve_max:.4f}) | {r.l1:.3e} | "
                f"{r.l2:.3e} | {r.linf:.3e} | {order} |" + cells
            )
        return "\n".join(lines)

    def summary(self) -> str:
        """The one-off costs, one line each."""
        lines = [
            f"first solve of {name} (compile or load from cache): {seconds:.2f} s"
            for name, seconds in self.warmup_seconds.items()
        ]
        if self.import_seconds is not None:
            lines.append(f"import conslaw in a fresh process: {self.import_seconds:.2f} s")
        return "\n".join(lines)


def _format(value: float | None, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def margin_error(result: Any) -> float | None:
    """Largest distance of a tracked margin at ``t_end`` from the exact one (None if the run
    has no tracked margins or the exact solution no margins)."""
    exact_margins = getattr(result.exact_solution, "margins", None)
    if result.margins is None or exact_margins is None:
        return None
    last = result.margins[-1]
    rear, front = exact_margins(float(last[0]))
    distances = [abs(x - e) for x, e in ((last[1], rear), (last[3], front)) if x == x]
    return max(distances) if distances else None


def measure_import_seconds() -> float | None:
    """Wall time of ``import conslaw`` and the built-in models in a fresh interpreter."""
    code = (
        "import time; t = time.perf_counter(); import conslaw, conslaw.simulation; "
        "from conslaw import registry; registry.models.names(); "
        "print(time.perf_counter() - t)"
    )
    try:
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
        )
        return float(out.stdout.strip())
    except (subprocess.SubprocessError, ValueError, OSError):
        return None


def _study_variants(
    scene: str | Path,
    coarsest: int,
    reconstructors: Sequence[str] | None,
    schemes: Sequence[str] | None,
    overrides: Mapping[str, Any] | None,
) -> tuple[Scene, list[Scene]]:
    """The scene of a study and its variants (one per scheme and reconstructor, a scheme without
    a reconstructor once), each validated and checked to have an exact solution on the coarsest
    grid, before any work is done."""
    base = load_scene(scene, overrides)
    base = replace(base, output_times=(base.t_end,), exact=True)
    reconstructors = list(reconstructors or [base.reconstructor])
    schemes = list(schemes or [base.scheme])
    # Validate every combination before any work is done.
    variants: list[Scene] = []
    for scheme in schemes:
        for reconstructor in reconstructors:
            variant = scheme_variants(
                scene, [scheme], {**(overrides or {}), "reconstructor": reconstructor}
            )[0]
            labels = (variant.scheme_label, variant.reconstructor_label)
            # A scheme without a reconstructor is studied once, not once per reconstructor.
            if labels not in {(v.scheme_label, v.reconstructor_label) for v in variants}:
                variants.append(variant)
    for variant in variants:
        model = variant.model_instance()
        grid = Grid(variant.x_min, variant.x_max, coarsest)
        exact, why = exact_solution_for(variant, model, grid)
        if exact is None:
            raise ConfigError(
                f"scene '{base.name}' has no exact solution to measure against ({why}); "
                "convergence needs one"
            )
    return base, variants


def convergence_study(
    scene: str | Path,
    cells: Sequence[int],
    reconstructors: Sequence[str] | None = None,
    schemes: Sequence[str] | None = None,
    repeats: int = 3,
    overrides: Mapping[str, Any] | None = None,
    measure_import: bool = True,
) -> ConvergenceStudy:
    """Run the study (see the module docstring); refuses scenes without an exact solution."""
    cells = sorted({int(n) for n in cells})
    if not cells or cells[0] < 4:
        raise ConfigError(f"--cells: expected integers >= 4, got {cells}")
    if isinstance(repeats, bool) or not isinstance(repeats, int) or not 1 <= repeats <= MAX_REPEATS:
        raise ConfigError(
            f"--repeats: expected an integer >= 1 and <= {MAX_REPEATS}, got {shown(repeats)}"
        )
    if is_two_dimensional(_model_of(scene, overrides)):
        study = _study_2d(scene, cells, reconstructors, schemes, repeats, overrides)
        if measure_import:
            study.import_seconds = measure_import_seconds()
        return study
    base, variants = _study_variants(scene, cells[0], reconstructors, schemes, overrides)
    study = ConvergenceStudy(str(base.name), base.t_end, repeats)
    for variant in variants:
        key = f"{variant.scheme_label}/{variant.reconstructor_label}"
        started = time.perf_counter()
        first = simulate(replace(variant, n_cells=cells[0], output_times=(variant.t_end,)))
        study.warmup_seconds[key] = time.perf_counter() - started
        if first.errors[-1] is None:
            raise ConfigError(
                f"scene '{base.name}' has no exact solution to measure against "
                f"({first.exact_note}); convergence needs one"
            )
        errors: list[float] = []
        margin_errors: list[float | None] = []
        for n in cells:
            sized = replace(variant, n_cells=n, output_times=(variant.t_end,))
            timings = []
            for _ in range(repeats):
                result = simulate(sized)
                timings.append(result.solve_seconds)
            norms = result.errors[-1]
            assert norms is not None
            errors.append(norms.l1)
            margin_errors.append(margin_error(result))
            pair = margin_errors[-2:]
            order_margin = (
                observed_orders(cells[len(errors) - 2 : len(errors)], pair)[0]  # type: ignore[arg-type]
                if len(pair) == 2 and None not in pair and 0.0 not in pair
                else None
            )
            order = (
                None
                if len(errors) < 2
                else observed_orders(cells[len(errors) - 2 : len(errors)], errors[-2:])[0]
            )
            study.rows.append(
                ConvergenceRow(
                    variant.scheme_label, variant.reconstructor_label, n, result.steps,
                    statistics.median(timings), min(timings), max(timings),
                    norms.l1, norms.l2, norms.linf, order, margin_errors[-1], order_margin,
                )
            )  # fmt: skip
    if measure_import:
        study.import_seconds = measure_import_seconds()
    return study


def _model_of(scene: str | Path, overrides: Mapping[str, Any] | None) -> dict[str, Any]:
    """``{"model": name}`` of a scene file after the overrides."""
    _, path = scene_path(scene)
    return {"model": (overrides or {}).get("model", read_scene_file(path).get("model"))}


def _study_2d(
    scene: str | Path,
    cells: Sequence[int],
    reconstructors: Sequence[str] | None,
    schemes: Sequence[str] | None,
    repeats: int,
    overrides: Mapping[str, Any] | None,
) -> ConvergenceStudy:
    """The study of a 2D scene: ``N`` is the number of cells along x; along y the scene's
    aspect ratio is kept (``ny = max(4, round(N ny0 / nx0))``). Every variant is validated and
    checked to have an exact solution before any work is done."""
    base = load_scene_2d(scene, overrides)
    variants = []
    for scheme in schemes or [base.scheme]:
        for reconstructor in reconstructors or [base.reconstructor]:
            changed = {**(overrides or {}), "scheme": scheme, "reconstructor": reconstructor}
            variants.append(load_scene_2d(scene, changed))

    def sized(variant: Scene2D, n: int) -> Scene2D:
        ny = max(4, round(n * variant.ny / variant.nx))
        return replace(variant, nx=n, ny=ny, output_times=(variant.t_end,), exact=True)

    for variant in variants:
        small = sized(variant, cells[0])
        model = small.model_instance()
        grid = Grid2D.from_bounds(
            small.x_min, small.x_max, small.nx, small.y_min, small.y_max, small.ny
        )
        exact, why = exact_solution_2d(small, model, grid)
        if exact is None:
            raise ConfigError(
                f"scene '{base.name}' has no exact solution to measure against ({why}); "
                "convergence needs one"
            )
    study = ConvergenceStudy(str(base.name), base.t_end, repeats)
    for variant in variants:
        key = f"{variant.scheme}/{variant.reconstructor}"
        started = time.perf_counter()
        simulate_2d(sized(variant, cells[0]))
        study.warmup_seconds[key] = time.perf_counter() - started
        errors: list[float] = []
        for n in cells:
            timings = []
            for _ in range(repeats):
                result = simulate_2d(sized(variant, n))
                timings.append(result.solve_seconds)
            norms = result.errors[-1]
            assert norms is not None
            errors.append(norms.l1)
            order = (
                None
                if len(errors) < 2
                else observed_orders(cells[-2 + len(errors) : len(errors)], errors[-2:])[0]
            )
            study.rows.append(
                ConvergenceRow(
                    variant.scheme, variant.reconstructor, n, result.steps,
                    statistics.median(timings), min(timings), max(timings),
                    norms.l1, norms.l2, norms.linf, order,
                )
            )  # fmt: skip
    return study


def _csv_text(study: ConvergenceStudy) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(asdict(study.rows[0])))
    writer.writeheader()
    for row in study.rows:
        writer.writerow(asdict(row))
    return buffer.getvalue()


def write_study(study: ConvergenceStudy, folder: Path) -> list[Path]:
    """Write ``convergence.md`` (table), ``.csv``, ``.json`` and the two PNGs; atomic writes."""
    from conslaw.io import atomic_write_bytes, prepare_output_dir, write_figure
    from conslaw.plotting import error_against_cells_figure, error_against_time_figure

    folder = prepare_output_dir(folder)
    stem = f"convergence-{study.scene}"
    document = {
        "scene": study.scene,
        "t_end": study.t_end,
        "repeats": study.repeats,
        "warmup_seconds": study.warmup_seconds,
        "import_seconds": study.import_seconds,
        "rows": [asdict(row) for row in study.rows],
    }
    written = [
        atomic_write_bytes(
            folder / f"{stem}.md", (study.table() + "\n\n" + study.summary() + "\n").encode()
        ),
        atomic_write_bytes(folder / f"{stem}.csv", _csv_text(study).encode()),
        atomic_write_bytes(folder / f"{stem}.json", json.dumps(document, indent=2).encode()),
    ]
    import matplotlib.pyplot as plt

    for name, build in (
        (f"{stem}-error-vs-time.png", error_against_time_figure),
        (f"{stem}-error-vs-cells.png", error_against_cells_figure),
    ):
        figure = build(study)
        written.append(write_figure(folder / name, figure))
        plt.close(figure)
    return written
