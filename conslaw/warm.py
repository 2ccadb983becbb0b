"""Compile the kernels of a set of scenes ahead of their first run (``conslaw warm``).

A first run of a model compiles its kernels for about 15 s (docs/performance.md). This
compiles every kernel family the scenes need, each once (scenes that share a kernel are grouped
by the name of their generated module), in parallel processes, so that later runs load them
from the cache.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any

from conslaw import registry


def warm(
    scenes: Sequence[str] | None = None,
    jobs: int | None = None,
    report: Callable[[str], None] = print,
) -> int:
    """Compile the kernels of ``scenes`` (default: every built-in scene) in up to ``jobs``
    processes (default: the number of cores); ``report`` gets a line per kernel family. Returns
    how many families were compiled (0 when all were cached)."""
    from conslaw.scene2d import Scene2D, load_any_scene
    from conslaw.simulation import build
    from conslaw.simulation2d import build_2d

    names = list(scenes) if scenes is not None else sorted(registry.scenes.names())
    families: dict[str, str] = {}
    for name in names:
        scene = load_any_scene(name)
        scheme: Any = build_2d(scene)[2] if isinstance(scene, Scene2D) else build(scene)[2]
        key = scheme.kernel_identity()
        if key is not None and key not in families and scheme.needs_compile():
            families[key] = name
    if not families:
        report("every kernel these scenes need is compiled already")
        return 0
    workers = max(1, min(jobs or os.cpu_count() or 1, len(families)))
    report(f"compiling {len(families)} kernel families in {workers} processes ...")
    context = multiprocessing.get_context("spawn")  # a fresh interpreter: no inherited JIT state
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(_compile_scene, name) for name in families.values()]
        for future in as_completed(futures):
            name, label, seconds = future.result()
            report(f"  {label} (as for {name}): {seconds:.1f} s")
    return len(families)


def _compile_scene(name: str) -> tuple[str, str, float]:
    """In a worker: compile what a run of scene ``name`` needs; (name, what, seconds)."""
    from conslaw.scene2d import load_any_scene

    started = time.perf_counter()
    label = compile_kernels(load_any_scene(name))
    return name, label or "", time.perf_counter() - started


def compile_kernels(
    scene: Any, only_missing: bool = False, announce: Callable[[str], None] | None = None
) -> str | None:
    """Compile (or load from the cache) the kernels a run of ``scene`` (a loaded 1D or 2D
    scene) needs, in this process; returns what was compiled (``nessyahu-tadmor kernels for
    savage-hutter, phi > delta``), or None when ``only_missing`` and they are cached.
    ``announce(label)`` is told before a compile starts."""
    from conslaw.scene2d import Scene2D
    from conslaw.simulation import build, kernel_label
    from conslaw.simulation2d import build_2d

    if isinstance(scene, Scene2D):
        scheme = build_2d(scene)[2]
        label = f"{scene.scheme} kernels for {scene.model}"
        initial = None
    else:
        model, _, scheme, initial, _ = build(scene)
        label = f"{scene.scheme} kernels for {kernel_label(scene, model)}"
    if only_missing and not scheme.needs_compile():
        return None
    if announce is not None:
        announce(label)
    if initial is None:
        scheme.compile()
    else:
        scheme.compile(initial)
        scheme.cell_coefficients(initial)  # the model's array kernels, used at every output
    return label
