"""The ``conslaw`` command: ``list``, ``show``, ``run``, ``convergence``, ``compare``,
``reproduce``.

Errors in the input become one line on stderr and exit code 2, without a traceback.
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from conslaw.errors import ConslawError

if TYPE_CHECKING:
    from conslaw.config import Scene
    from conslaw.io import RunWriter
    from conslaw.scene2d import Scene2D
    from conslaw.simulation import RunResult

EXIT_INPUT = 2
#: ``--quiet`` (docs/cli.md, "Progress"): before the command or after it.
QUIET_HELP = (
    "no progress output: no bar, no progress lines, no notice of a compile (errors and the "
    "summary at the end are still printed)"
)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        # argparse prints usage + message; we print one line (and keep exit code 2).
        sys.stderr.write(f"conslaw: error: {message} (see 'conslaw --help')\n")
        raise SystemExit(EXIT_INPUT)


def _overrides(pairs: Sequence[str]) -> dict[str, Any]:
    from conslaw.config import parse_value
    from conslaw.errors import ConfigError

    result: dict[str, Any] = {}
    for pair in pairs:
        key, separator, value = pair.partition("=")
        if not separator or not key.strip():
            raise ConfigError(f"--set expects key=value, got '{pair}'")
        result[key.strip()] = parse_value(value.strip())
    return result


def _command_list(args: argparse.Namespace) -> int:
    from conslaw import registry
    from conslaw.initial import INITIAL_KINDS
    from conslaw.initial2d import INITIAL_KINDS_2D

    sections: list[tuple[str, registry.Registry[Any]]] = [
        ("models", registry.models),
        ("schemes", registry.schemes),
        ("schemes_2d", registry.schemes_2d),
        ("reconstructors", registry.reconstructors),
        ("boundaries", registry.boundaries),
        ("scenes", registry.scenes),
    ]
    titles = {"boundaries": "boundary conditions", "schemes_2d": "2D schemes"}
    for kind, entries in sections:
        names = entries.names()
        print(f"{titles.get(kind, kind)} ({len(names)}):")
        for name in names:
            print(f"  {name:<20} {registry.description_of(kind, name)}")
    for title, generic, two_d in (
        ("initial conditions", INITIAL_KINDS, False),
        ("initial conditions of 2D scenes", INITIAL_KINDS_2D, True),
    ):
        own = [
            (kind, f"{description} ({model_name} only)")
            for model_name in registry.models.names()
            if (registry.models.get(model_name).flux_y_point is not None) == two_d
            for kind, (_, _, description) in registry.models.get(model_name).initial_kinds.items()
        ]
        print(f"{title} ({len(generic) + len(own)}):")
        for name, description in [*((k, v[2]) for k, v in generic.items()), *own]:
            print(f"  {name:<20} {description}")
    return 0


def _command_show(args: argparse.Namespace) -> int:
    import tomli_w

    from conslaw.scene2d import Scene2D, load_any_scene

    scene = load_any_scene(args.scene, _overrides(args.set))
    # What a run would refuse before its first step (the initial data, the memory), said
    # before the scene is printed as valid.
    if isinstance(scene, Scene2D):
        from conslaw.simulation2d import build_2d

        build_2d(scene)
    else:
        from conslaw.simulation import build

        build(scene)
    sys.stdout.write(tomli_w.dumps(scene.to_table()))
    return 0


def _notice(message: str) -> None:
    """A line on stdout before a wait (stderr is kept for the one-line errors)."""
    print(f"conslaw: {message}", flush=True)


def _reporter(quiet: bool) -> Callable[[str], None]:
    """Where a study's or a calibration's progress lines go: stdout, flushed at once (a log
    file shows each as it comes), or nowhere with ``--quiet``."""
    if quiet:
        return lambda line: None
    return lambda line: print(f"conslaw: {line}", flush=True)


def _command_run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from conslaw.figure_worker import FigureWorker, write_figures
    from conslaw.io import RunWriter, check_output_dir
    from conslaw.scene2d import Scene2D, load_any_scene

    loaded = load_any_scene(args.scene, _overrides(args.set))
    if args.no_plot:
        loaded = replace(loaded, plot=False)
    out = _out_folder(args.out, Path("conslaw-output") / loaded.name)
    check_output_dir(out)
    if isinstance(loaded, Scene2D):
        from conslaw.output.writer2d import RunWriter2D
        from conslaw.plotting2d import write_figures_2d
        from conslaw.simulation2d import simulate_2d
        from conslaw.terrain.hazard_maps import hazard_output_files

        writer_2d = RunWriter2D(out, loaded, write_figures_2d, hazard_output_files)
        try:
            writer_2d.claim()
            return _run_scene(loaded, out, writer_2d, (simulate_2d, _print_summary_2d), args.quiet)
        finally:
            writer_2d.release()
    from conslaw.simulation import simulate

    scene = loaded
    # Fork the figure child before the kernels load (matplotlib's import overlaps the solve).
    worker = FigureWorker.start() if scene.plot else None
    writer = RunWriter(out, scene, functools.partial(write_figures, worker=worker))
    try:
        writer.claim()
        return _run_scene(scene, out, writer, (simulate, _print_summary), args.quiet)
    finally:
        writer.release()
        if worker is not None:
            worker.close()


def _run_scene(
    scene: Any,
    out: Path,
    writer: RunWriter,
    how: tuple[Callable[..., Any], Callable[[Any, Any], None]],
    quiet: bool,
) -> int:
    """Run ``scene`` by ``simulate`` (:func:`conslaw.simulation.simulate` or
    :func:`conslaw.simulation2d.simulate_2d`) writing through ``writer``, then print
    ``summary(scene, result)`` (``how = (simulate, summary)``); the exit code (see
    :func:`_command_run`). The progress (a bar on a terminal, else a line now and then;
    :class:`conslaw.progress.RunProgress`) and the notice of a compile are left out when
    ``quiet``; the summary is not."""
    from conslaw import signals
    from conslaw.errors import RunInterrupted
    from conslaw.progress import RunProgress

    simulate, summary = how
    latch = signals.SignalLatch()
    bar = RunProgress(scene.t_end, show=not quiet, check=latch.check)

    def on_output(result: Any) -> None:
        writer(result)
        latch.check()

    try:
        with signals.handled(latch):
            notice = None if quiet else _notice
            result = simulate(scene, progress=bar, on_output=on_output, notice=notice)
    except RunInterrupted as interrupted:
        bar.close()
        if writer.last_time != interrupted.last_output:  # the signal came as it finished one
            interrupted = RunInterrupted(
                interrupted.t, interrupted.steps, writer.last_time, interrupted.signal_number
            )
        where = f" in {out}" if writer.last_time is not None else ""
        sys.stderr.write(f"conslaw: {interrupted}{where}\n")
        return 128 + interrupted.signal_number
    except ConslawError as failure:
        if writer.last_time is None:
            raise
        bar.close()
        kept = f"outputs up to t={writer.last_time:.6g} are complete in {out}"
        raise type(failure)(f"{failure}; {kept}") from None
    finally:
        bar.close()
    try:
        files = writer.finish(result)
    except ConslawError as failure:
        kept = f"outputs up to t={writer.last_time:.6g} are complete in {out}"
        raise type(failure)(f"{failure}; {kept}") from None
    except KeyboardInterrupt:
        sys.stderr.write(
            f"conslaw: interrupted while drawing the figures after the run reached "
            f"t={result.final.t:g} ({result.steps} steps); every output is complete in {out}\n"
        )
        return 130
    summary(scene, result)
    for path in files:
        print(f"  wrote {path}")
    return 0


def _print_solve_and_errors(scene: Any, result: Any, reconstructor: str, cells: str) -> None:
    """The first lines of a run's summary: what ran and how long, then the error against the
    exact cell averages at every output time (or why there is no comparison)."""
    print(
        f"{scene.name}: {scene.model}, {scene.scheme}, {reconstructor}, {cells}, "
        f"t={result.final.t:g}, {result.steps} steps, solve {result.solve_seconds:.3f} s "
        f"(compile or cache load {result.compile_seconds:.2f} s)"
    )
    for state, error in zip(result.states, result.errors, strict=True):
        if error is not None:
            print(
                f"  t={state.t:g}: error in {result.model.variables[0]} against exact cell "
                f"averages  L1={error.l1:.4e}  L2={error.l2:.4e}  Linf={error.linf:.4e}"
            )
    if result.exact_solution is None and scene.exact:
        print(f"  no comparison with an exact solution: {result.exact_note}")


def _print_summary_2d(scene: Scene2D, result: Any) -> None:
    """What a finished 2D run prints: the solve, the errors against the exact solution, the
    change of the conserved totals; on terrain what the states hold and, for GeoTIFFs from a
    terrain without a CRS, that they carry none
    (:func:`conslaw.terrain.hazard_maps.terrain_run_notes`)."""
    from conslaw.terrain.hazard_maps import terrain_run_notes

    cells = f"{scene.nx} x {scene.ny} cells"
    _print_solve_and_errors(scene, result, scene.reconstructor, cells)
    closed = set(scene.boundaries.values()) <= {"periodic", "wall"}
    where = (
        "closed domain: round-off only"
        if closed
        else "open boundaries: what flowed in or out, not a conservation error"
    )
    model = result.model
    rows = model.conserved_rows()
    if "wall" in scene.boundaries.values() and model.depth_index is not None:
        rows = (model.depth_index,)  # a wall pushes on the momentum
    drift = ", ".join(f"{model.variables[v]} {result.mass_drift[v]:+.2e}" for v in rows)
    if drift:
        print(f"  relative change of conserved totals from t=0 ({where}): {drift}")
    lowest = min(float(state.q[0].min()) for state in result.states)
    print(f"  smallest {result.model.variables[0]} at the outputs: {lowest:.3g}")
    for note in result.scheme_notes:
        print(f"  note: {note}")
    momenta = [v for v in (model.momentum_index, model.momentum_y_index) if v is not None]
    if momenta:
        largest = ", ".join(
            f"|{model.variables[v]}| {float(abs(result.final.q[v]).max()):.2e}" for v in momenta
        )
        print(f"  largest momenta at t={result.final.t:g}: {largest}")
    if scene.initial.kind == "still-water":
        change = float(abs(result.final.q - result.initial.q).max())
        print(
            f"  largest change of any value from t=0: {change:.2e} (water at rest stays at "
            "rest; an error above is the sampling of the bed in the cell averages at t=0)"
        )
    for note in terrain_run_notes(result, scene.output_formats):
        print(f"  note: {note}")
    if result.stop is not None:
        print(f"  {result.stop.summary()}")


def _print_summary(scene: Scene, result: RunResult) -> None:
    """What a finished run prints before the files it wrote: the solve, the errors against the
    exact solution, the change of the conserved totals, whether the material is at rest."""
    _print_solve_and_errors(scene, result, scene.reconstructor_label, f"N={scene.n_cells}")
    rows = result.model.conserved_rows()
    if rows:
        import numpy as np

        # Relative to the total's size at t=0; a variable that is 0 everywhere at t=0 (the
        # momentum of a dam break) has no size to compare with: its change is absolute.
        started_empty = ~np.any(result.initial.q, axis=1)
        drift = ", ".join(
            f"{result.model.variables[v]} {result.mass_drift[v]:+.2e}"
            + (" (absolute: 0 at t=0)" if started_empty[v] else "")
            for v in rows
        )
        closed = {scene.left.kind, scene.right.kind} <= {"periodic", "wall"}
        where = (
            "closed domain: round-off only"
            if closed
            else "open boundaries: what flowed in or out, not a conservation error"
        )
        print(f"  relative change of conserved totals from t=0 ({where}): {drift}")
    rest = _rest_note(result)
    if rest is not None:
        print(f"  {rest}")
    note = result.outflow_fed_note()
    if note is not None:
        print(f"  note: {note}")


def _rest_note(result: Any) -> str | None:
    """For a model with a momentum: whether the material is at rest at the end (every
    momentum exactly 0), or the largest momentum, when the run ends with less than a
    thousandth of the largest momentum it saved (coming to rest, or held)."""
    import numpy as np

    row = result.model.momentum_index
    if row is None:
        return None
    largest = max(float(np.abs(state.q[row]).max()) for state in result.states)
    final = float(np.abs(result.final.q[row]).max())
    if final == 0.0:
        return f"at rest at t={result.final.t:g}: every momentum is exactly 0"
    if largest > 0.0 and final < 1e-3 * largest:
        return f"largest |{result.model.variables[row]}| at t={result.final.t:g}: {final:.2e}"
    return None


def _out_folder(given: str | None, default: Path) -> Path:
    """The ``--out`` folder: the one given, else ``default``; an empty name is refused (it
    would otherwise mean the default silently)."""
    from conslaw.errors import ConfigError

    if given is None:
        return default
    if not given.strip():
        raise ConfigError("--out: expected a folder name, got an empty one")
    return Path(given)


def _names(text: str | None) -> list[str] | None:
    return None if text is None else [part.strip() for part in text.split(",") if part.strip()]


def _command_convergence(args: argparse.Namespace) -> int:
    from conslaw.errors import ConfigError
    from conslaw.io import check_output_dir, prepare_output_dir
    from conslaw.studies.convergence import convergence_study, write_study

    try:
        cells = [int(part) for part in args.cells.split(",") if part.strip()]
    except ValueError:
        raise ConfigError(
            f"--cells: expected integers separated by commas, got '{args.cells}'"
        ) from None
    out = _out_folder(args.out, Path("conslaw-output") / "convergence")
    check_output_dir(out)  # made only once the study has run
    study = convergence_study(
        args.scene, cells, _names(args.reconstructor), _names(args.scheme), args.repeats,
        _overrides(args.set),
    )  # fmt: skip
    prepare_output_dir(out)
    print(study.table())
    print(study.summary())
    for path in write_study(study, out):
        print(f"wrote {path}")
    return 0


def _command_reproduce(args: argparse.Namespace) -> int:
    from conslaw.io import check_output_dir
    from conslaw.studies.reproduce import reproduce_paper

    out = _out_folder(args.out, Path("conslaw-output") / "paper")
    check_output_dir(out)
    started = time.perf_counter()
    files = reproduce_paper(out)
    for path in files:
        print(f"wrote {path}")
    print(f"reproduce {args.target}: {time.perf_counter() - started:.1f} s")
    return 0


def _command_compare(args: argparse.Namespace) -> int:
    from conslaw.errors import ConfigError
    from conslaw.io import check_output_dir
    from conslaw.studies.comparison import compare, write_comparison

    schemes = _names(args.scheme) or []
    if not schemes:
        raise ConfigError(
            "--scheme: expected comma-separated schemes, e.g. nessyahu-tadmor,lagrangian"
        )
    out = _out_folder(args.out, Path("conslaw-output") / "compare")
    check_output_dir(out)
    comparison = compare(args.scene, schemes, _overrides(args.set))
    print(comparison.table())
    print(comparison.notes())
    for path in write_comparison(comparison, out):
        print(f"wrote {path}")
    return 0


def _command_warm(args: argparse.Namespace) -> int:
    from conslaw.errors import ConfigError
    from conslaw.warm import warm

    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"--jobs: expected an integer >= 1, got {args.jobs}")
    if not args.quiet:
        warm(args.scenes or None, args.jobs, report=lambda line: print(line, flush=True))
        return 0
    # --quiet: not a line per kernel family as it is compiled, one line at the end
    compiled = warm(args.scenes or None, args.jobs, report=lambda line: None)
    print(
        f"compiled {compiled} kernel families"
        if compiled
        else "every kernel these scenes need is compiled already"
    )
    return 0


def _thresholds(pairs: Sequence[str], scene: str, settings: dict[str, Any]) -> dict[str, float]:
    """``--threshold FIELD=VALUE`` pairs, checked before the study runs: a map the scene's
    members keep (:data:`conslaw.ensemble.summary.FIELD_NAMES`), a finite value, each field
    once."""
    import math

    from conslaw.ensemble.summary import FIELD_NAMES
    from conslaw.errors import ConfigError
    from conslaw.scene2d import Scene2D, load_any_scene

    if not pairs:
        return {}
    dimension = 2 if isinstance(load_any_scene(scene, settings), Scene2D) else 1
    chosen: dict[str, float] = {}
    for pair in pairs:
        name, _, value = (part.strip() for part in pair.partition("="))
        try:
            number = float(value)
        except ValueError:
            number = math.nan
        if name not in FIELD_NAMES[dimension]:
            known = ", ".join(FIELD_NAMES[dimension])
            raise ConfigError(f"--threshold {name}: not a map of this scene's members ({known})")
        if not math.isfinite(number):
            raise ConfigError(f"--threshold expects FIELD=NUMBER (a finite number), got '{pair}'")
        if name in chosen:
            raise ConfigError(f"--threshold {name} given twice")
        chosen[name] = number
    return chosen


def _command_ensemble(args: argparse.Namespace) -> int:
    import numpy as np

    from conslaw.ensemble import StudyInterrupted, run_study
    from conslaw.ensemble.products import quantile_table, rank_correlations, write_products
    from conslaw.errors import ConfigError

    if args.threshold and not args.fields:
        raise ConfigError("--threshold needs the members' maps: add --fields")
    thresholds = _thresholds(args.threshold, args.scene, _overrides(args.set))
    out = _out_folder(args.out, Path("conslaw-output") / f"ensemble-{Path(args.scene).stem}")
    options = {
        "fields": args.fields, "depth_threshold": args.depth_threshold, "format": args.format,
        "scheduler": args.scheduler, "workers": args.workers, "resume": args.resume,
    }  # fmt: skip
    try:
        study = run_study(
            args.scene, args.vary, args.samples, out, design=args.design, seed=args.seed,
            settings=_overrides(args.set), options=options,
            report=_reporter(args.quiet),
        )  # fmt: skip
    except StudyInterrupted as interrupted:
        sys.stderr.write(f"conslaw: {interrupted}\n")
        return 128 + interrupted.signal_number
    dataset = study.dataset
    counts = {str(s): int((dataset.status.values == s).sum()) for s in set(dataset.status.values)}
    print(", ".join(f"{count} {status}" for status, count in sorted(counts.items())))
    print(f"{study.ran} members run in {study.wall_seconds:.1f} s on {study.workers} workers")
    for name, count, low, mid, high in quantile_table(dataset):
        print(f"  {name}: 5% {low:.4g}, median {mid:.4g}, 95% {high:.4g} ({count} members)")
    resting = int(np.sum(dataset["at_rest"].values == 1.0))
    print(f"  {resting} members at rest at the end (every momentum exactly 0)")
    cut = int(np.sum(dataset["at_boundary"].values == 1.0))
    if cut:
        print(f"  {cut} members reached an end of the domain: their run-out is cut short")
    correlations = rank_correlations(dataset)
    for figure in ("runout_length", "travel_angle"):
        if figure in correlations["figure"]:
            row = correlations.sel(figure=figure)
            text = ", ".join(
                f"{p} {float(row.sel(parameter=p)):+.2f}".replace("+nan", "n/a")
                for p in row["parameter"].values
            )
            print(f"  rank correlation of {figure} with {text}")
    import os

    from conslaw.output.files import hold_folder

    held = hold_folder(out, "conslaw study")  # no other study writes into it meanwhile
    try:
        products = write_products(dataset, out, thresholds, plot=not args.no_plot)
    finally:
        if held is not None:
            os.close(held)
    files = [study.path, *products]
    for path in files:
        print(f"  wrote {path}")
    failed = [i for i, s in enumerate(dataset.status.values) if s != "finished"]
    for index in failed[:5]:
        print(f"  member {index} {dataset.status.values[index]}: {dataset.message.values[index]}")
    return 0


def _add_quiet(parser: argparse.ArgumentParser) -> None:
    """``--quiet`` after a command (before it, it is the main parser's; given in neither place
    it is False)."""
    parser.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                        help=QUIET_HELP)  # fmt: skip


def _add_engine_options(parser: argparse.ArgumentParser) -> None:
    """Where the members of a study or calibration run: ``--scheduler``, ``--workers``."""
    parser.add_argument("--scheduler", help="a Dask scheduler address, e.g. tcp://host:8786")
    parser.add_argument(
        "--workers",
        type=int,
        help="local processes (default and at most: one per core; at most one per member)",
    )


def _add_ensemble(commands: Any) -> None:
    from conslaw.ensemble.dataset import FORMATS
    from conslaw.ensemble.design import DESIGNS, DISTRIBUTIONS

    study = commands.add_parser(
        "ensemble", help="run many members of a scene with varied keys; one labelled dataset"
    )
    study.add_argument("scene", help="built-in scene name or path to a .toml file")
    kinds = ", ".join(f"{name}:{args}" for name, args in DISTRIBUTIONS.items())
    study.add_argument(
        "--vary", action="append", required=True, metavar="KEY=DISTRIBUTION:ARGS",
        help=f"a varied scene key, e.g. parameters.delta=uniform:20:30 ({kinds})",
    )  # fmt: skip
    study.add_argument("--samples", type=int, required=True, help="members")
    study.add_argument("--design", default="lhs", choices=DESIGNS, help="sample design (lhs)")
    study.add_argument(
        "--seed", type=int, default=0, help="the same seed, the same members (0 to 2**64 - 1)"
    )
    study.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    study.add_argument("--out", help="study folder (default conslaw-output/ensemble-SCENE)")
    study.add_argument("--resume", action="store_true", help="run only the missing members")
    study.add_argument("--fields", action="store_true", help="keep every member's maps")
    study.add_argument(
        "--threshold", action="append", default=[], metavar="FIELD=VALUE",
        help="exceedance probability of a map, e.g. peak_depth=1.0 (needs --fields)",
    )  # fmt: skip
    study.add_argument("--format", default="netcdf", choices=list(FORMATS), help="dataset format")
    _add_engine_options(study)
    study.add_argument("--depth-threshold", type=float, help="covered depth, 1D figures")
    study.add_argument("--no-plot", action="store_true", help="no figures")
    _add_quiet(study)


def _command_calibrate(args: argparse.Namespace) -> int:
    from conslaw.ensemble.calibration import calibrate

    out = _out_folder(args.out, Path("conslaw-output") / f"calibrate-{Path(args.scene).stem}")
    options = {
        "scheduler": args.scheduler, "workers": args.workers, "coarse": args.coarse,
        "plot": not args.no_plot,
    }  # fmt: skip
    result = calibrate(
        args.scene, args.observed, args.fit, settings=_overrides(args.set),
        tolerance=args.tolerance, seed=args.seed, out=out, options=options,
        report=_reporter(args.quiet),
    )  # fmt: skip
    for key in result.keys:
        error = result.standard_error[key.key]
        print(f"{key.key} = {result.fitted[key.key]:.6g} ± {error:.2g} (standard error; start "
              f"{key.start:g}, bounds {key.low:g}:{key.high:g})")  # fmt: skip
    best = result.best
    for observation in result.observations:
        if observation.deposit is None:
            print(f"  {observation.name}: model {best.figures[observation.name]:.6g}, observed "
                  f"{observation.value:.6g} ± {observation.sigma:.2g}")  # fmt: skip
    uncertainty = result.uncertainty
    print(
        f"misfit {result.misfit:.4g}; {len(result.evaluations)} members in "
        f"{result.wall_seconds:.1f} s, {result.failed} failed ({uncertainty.failed} of the "
        f"{uncertainty.members} uncertainty members)"
    )
    for note in result.notes:
        print(f"  note: {note}")
    for path in result.files:
        print(f"  wrote {path}")
    return 0


def _add_calibrate(commands: Any) -> None:
    from conslaw.ensemble.fitting import COARSE_PER_KEY
    from conslaw.ensemble.observations import RELATIVE_ERROR

    fit = commands.add_parser(
        "calibrate", help="fit scene keys to observed figures (run-out, travel angle, deposit)"
    )
    fit.add_argument("scene", help="built-in scene name or path to a .toml file")
    fit.add_argument(
        "--observed", action="append", default=[], metavar="NAME=VALUE",
        help="an observed summary figure, e.g. runout_length=33.67, or deposit=FILE (1D: CSV "
        "of x, depth; 2D: GeoTIFF or ESRI ASCII grid)",
    )  # fmt: skip
    fit.add_argument(
        "--fit", action="append", default=[], metavar="KEY=LOW:HIGH",
        help="a fitted scene key and its bounds, e.g. parameters.delta=20:35; it starts from "
        "the scene's value",
    )  # fmt: skip
    fit.add_argument(
        "--tolerance", action="append", default=[], metavar="NAME=SIGMA",
        help=f"standard error of an observation (default {RELATIVE_ERROR:g} of its magnitude)",
    )  # fmt: skip
    fit.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    fit.add_argument(
        "--seed", type=int, default=0, help="the same seed, the same calibration (0 to 2**64 - 1)"
    )
    fit.add_argument(
        "--coarse", type=int, help=f"members of the coarse stage ({COARSE_PER_KEY} per key)"
    )
    fit.add_argument("--out", help="output folder (default conslaw-output/calibrate-SCENE)")
    _add_engine_options(fit)
    fit.add_argument("--no-plot", action="store_true", help="no calibration.png")
    _add_quiet(fit)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for the documentation)."""
    parser = _Parser(
        prog="conslaw",
        description="Hyperbolic conservation laws in 1D and 2D, avalanches on terrain.",
    )
    from conslaw import __version__

    parser.add_argument("--version", action="version", version=f"conslaw {__version__}")
    parser.add_argument("-q", "--quiet", action="store_true", help=QUIET_HELP)
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    commands.add_parser("list", help="print every registered name with a one-line description")
    for name, text in (("run", "run a scene"), ("show", "print a scene with defaults filled in")):
        sub = commands.add_parser(name, help=text)
        sub.add_argument("scene", help="built-in scene name (conslaw list) or path to a .toml file")
        sub.add_argument(
            "--set",
            action="append",
            default=[],
            metavar="KEY=VALUE",
            help="override a scene key, e.g. --set n_cells=1600 --set boundary.left=wall",
        )
        if name == "run":
            sub.add_argument("--out", help="output folder (default conslaw-output/SCENE)")
            sub.add_argument("--no-plot", action="store_true", help="do not draw the figures (PNG)")
            _add_quiet(sub)
    study = commands.add_parser(
        "convergence", help="errors, observed orders and run times over a list of N"
    )
    study.add_argument("scene", help="a scene whose model has an exact solution")
    study.add_argument(
        "--cells",
        required=True,
        help="comma-separated N, e.g. 100,200,400 (a 2D scene: cells along x, y keeps the "
        "scene's aspect ratio)",
    )
    study.add_argument(
        "--reconstructor", help="comma-separated reconstructors (default: the scene's)"
    )
    study.add_argument("--scheme", help="comma-separated schemes (default: the scene's)")
    study.add_argument("--repeats", type=int, default=3, help="solves per N (median reported)")
    study.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    study.add_argument("--out", help="output folder (default conslaw-output/convergence)")
    reproduce = commands.add_parser(
        "reproduce", help="regenerate a paper's figures and a report of the errors"
    )
    reproduce.add_argument(
        "target",
        choices=["paper"],
        help="paper: Tai et al. (2001), Figs. 3, 4 and 5 and the Lagrangian comparison",
    )
    reproduce.add_argument("--out", help="output folder (default conslaw-output/paper)")
    warm = commands.add_parser(
        "warm", help="compile the kernels of the built-in scenes (or those named) ahead of use"
    )
    warm.add_argument("scenes", nargs="*", help="scene names or .toml files (default: built-in)")
    warm.add_argument("--jobs", type=int, help="processes at once (default: one per core)")
    warm.add_argument(
        "-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
        help="one line at the end instead of a line per kernel family as it is compiled",
    )  # fmt: skip
    versus = commands.add_parser(
        "compare", help="one scene with several schemes: one figure, a table of errors and times"
    )
    versus.add_argument("scene", help="built-in scene name or path to a .toml file")
    versus.add_argument(
        "--scheme",
        required=True,
        help="comma-separated schemes, options after a colon, e.g. "
        "nessyahu-tadmor,lagrangian,lagrangian:viscosity=0.02",
    )
    versus.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    versus.add_argument("--out", help="output folder (default conslaw-output/compare)")
    _add_ensemble(commands)
    _add_calibrate(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``conslaw`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {
        "list": _command_list,
        "show": _command_show,
        "run": _command_run,
        "convergence": _command_convergence,
        "reproduce": _command_reproduce,
        "compare": _command_compare,
        "warm": _command_warm,
        "ensemble": _command_ensemble,
        "calibrate": _command_calibrate,
    }
    try:
        with warnings.catch_warnings():
            # numpy's floating-point warnings (an overflow in an exact solution or a bed) are
            # not for the command line: every state is checked (finite, admissible) and a
            # failure is one line. From Python they show as usual.
            # shapely's too (an overflow in a release polygon's area): conslaw checks the result.
            warnings.filterwarnings(
                "ignore", category=RuntimeWarning, module=r"(numpy|conslaw|shapely)"
            )
            if args.command in ("run", "ensemble", "calibrate") and not args.quiet:
                from conslaw.progress import line_seconds

                line_seconds()  # a bad CONSLAW_PROGRESS_SECONDS before anything is made
            return handlers[args.command](args)
    except ConslawError as error:
        sys.stderr.write(f"conslaw: error: {error}\n")
        return EXIT_INPUT
    except KeyboardInterrupt:
        sys.stderr.write("conslaw: interrupted\n")
        return 130
    except MemoryError:
        # The run's estimate (conslaw.memory) let it start; the machine still ran out.
        fewer = {"ensemble": "members (--samples)", "calibrate": "members (--coarse)"}
        sys.stderr.write(
            f"conslaw: error: out of memory; use fewer {fewer.get(args.command, 'cells')} or "
            "output times (outputs already written are complete)\n"
        )
        return EXIT_INPUT
    except BrokenPipeError:
        # The reader went away (`conslaw list | head`): stop quietly, as other tools do.
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def console_main() -> int:
    """The ``conslaw`` console script: :func:`main`, then the interpreter's exit without its
    final garbage collection.

    The collection at exit walks every object numba and llvmlite made while loading the
    kernels, about 0.3 s (docs/performance.md, "The whole conslaw run process"). Nothing is left to
    finalise by then: every file is written and closed, and ``atexit`` handlers still run.
    ``gc.freeze`` is not used by :func:`main` itself, which tests call in one long process.
    """
    import gc

    code = main()
    gc.freeze()
    return code


if __name__ == "__main__":
    raise SystemExit(console_main())
