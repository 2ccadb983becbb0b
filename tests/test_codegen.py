"""Kernel generation (conslaw.kernelgen.generation): what recompiles, line numbers, stale modules,
threads."""

from __future__ import annotations

import importlib
import json
import os
import shutil
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import numpy as np
import pytest

import conslaw
from conslaw import registry
from conslaw.grid import Grid
from conslaw.kernelgen import generation as codegen
from conslaw.kernelgen.generation import dependency_sources, generate
from conslaw.reconstruct import Reconstructor, limiters
from conslaw.schemes.front_tracking.kernels import ft_kernels
from conslaw.schemes.nessyahu_tadmor import kernels as nt

TEMPLATE = """\
import numpy as np
from numba import njit

# --- bindings ---
from {package}.placeholder import twice as _twice

SCALE = 1.0
# --- end bindings ---


@njit(cache=True)
def apply(values):
    out = np.empty_like(values)
    for i in range(values.size):
        out[i] = SCALE * _twice(values[i])
    return out
"""

PHYSICS = """\
from numba import njit


@njit(cache=True)
def twice(x):
    return 2.0 * x
"""


@pytest.fixture
def package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[str, Path]:
    """A throw-away package with the bound function (``physics``), an unrelated sibling module
    (``other``) and a template, importable for the test's duration; kernels in ``tmp_path``."""
    name = f"codegen_case_{os.getpid()}_{abs(hash(tmp_path)) % 10**8}"
    folder = tmp_path / "src" / name
    folder.mkdir(parents=True)
    (folder / "__init__.py").write_text("")
    (folder / "placeholder.py").write_text(PHYSICS)
    (folder / "physics.py").write_text(PHYSICS)
    (folder / "other.py").write_text("VALUE = 1\n")
    (folder / "template.py").write_text(TEMPLATE.format(package=name))
    monkeypatch.syspath_prepend(str(tmp_path / "src"))
    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path / "kernels"))
    return name, folder


@pytest.fixture(params=["beside the module", "NUMBA_CACHE_DIR"])
def numba_cache(
    request: pytest.FixtureRequest, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> str:
    """numba's cache in ``__pycache__`` beside the generated modules, or under
    ``NUMBA_CACHE_DIR`` (which a user may set), whatever the environment of the tests says: in
    this process (``numba.config``) and in its children (the variable)."""
    import numba

    folder = ""
    if request.param == "NUMBA_CACHE_DIR":
        folder = str(tmp_path / "numba-cache")
        monkeypatch.setenv("NUMBA_CACHE_DIR", folder)
    else:
        monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(numba.config, "CACHE_DIR", folder)
    return folder


def generated(name: str, folder: Path) -> object:
    """The kernel of the test template bound to ``physics.twice``, as the code is now."""
    for module in [m for m in sys.modules if m.startswith(f"{name}.physics")]:
        del sys.modules[module]
    importlib.invalidate_caches()
    physics = importlib.import_module(f"{name}.physics")
    return generate(folder / "template.py", {"_twice": physics.twice}, {"SCALE": 3.0})


def test_only_the_bound_source_recompiles(package: tuple[str, Path], numba_cache: str) -> None:
    """Appending to a module the compiled code does not reach keeps the module (and numba's
    cache of it); appending to the bound function's file makes a new one. The version used last
    before it stays (two versions in use at once do not remove each other's kernels); the one
    before that is removed with numba's cache files of it, wherever numba keeps them (beside
    the module, or under ``NUMBA_CACHE_DIR``: the folder numba's own cache of the function
    names)."""
    name, folder = package
    first = generated(name, folder)
    np.testing.assert_array_equal(first.apply(np.array([1.0, 2.0])), [6.0, 12.0])
    with (folder / "other.py").open("a") as handle:
        handle.write("# a comment\n")
    assert generated(name, folder).__name__ == first.__name__
    kernels = Path(os.environ["CONSLAW_CACHE_DIR"])
    modules = []
    for _ in range(2):
        with (folder / "physics.py").open("a") as handle:
            handle.write("# a comment\n")
        modules.append(generated(name, folder))
        np.testing.assert_array_equal(modules[-1].apply(np.array([1.0])), [6.0])
    second, third = modules
    assert len({first.__name__, second.__name__, third.__name__}) == 3
    numba_folder = Path(second.apply._cache._cache_path)  # type: ignore[attr-defined]
    assert numba_folder == codegen.numba_cache_folder(kernels / f"{second.__name__}.py")
    assert numba_folder.is_relative_to(numba_cache or kernels)
    assert (kernels / f"{second.__name__}.py").exists()
    assert list(numba_folder.glob(f"{second.__name__}.*"))
    assert not (kernels / f"{first.__name__}.py").exists()
    assert not list(numba_folder.glob(f"{first.__name__}.*"))


def test_two_installations_of_the_same_code_share_their_kernels(
    package: tuple[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The kernel key names a file by its path inside its package, not by where the package is
    installed: the same package copied elsewhere (a source checkout beside site-packages) and
    imported from there binds to the same generated module, compiled once."""
    name, folder = package
    first = generated(name, folder)
    elsewhere = tmp_path / "elsewhere"
    shutil.copytree(folder, elsewhere / name)
    for module in [m for m in sys.modules if m == name or m.startswith(f"{name}.")]:
        del sys.modules[module]
    monkeypatch.syspath_prepend(str(elsewhere))
    importlib.invalidate_caches()
    physics = importlib.import_module(f"{name}.physics")
    assert Path(physics.__file__).is_relative_to(elsewhere)
    again = generate(elsewhere / name / "template.py", {"_twice": physics.twice}, {"SCALE": 3.0})
    assert again.__name__ == first.__name__
    assert codegen.package_path(elsewhere / name / "template.py") == f"{name}/template.py"
    assert codegen.package_path(tmp_path / "loose.py") == "loose.py"


def test_a_constant_the_bound_code_reads_is_part_of_the_key(package: tuple[str, Path]) -> None:
    """numba freezes a global into the compiled code: a changed constant in a module the bound
    function reads it from must change the kernel."""
    name, folder = package
    (folder / "physics.py").write_text(
        PHYSICS.replace("2.0 * x", "FACTOR * x") + f"\n\nfrom {name}.other import VALUE as FACTOR\n"
    )
    first = generated(name, folder)
    (folder / "other.py").write_text("VALUE = 5\n")
    del sys.modules[f"{name}.other"]
    second = generated(name, folder)
    assert second.__name__ != first.__name__
    np.testing.assert_array_equal(second.apply(np.array([1.0])), [15.0])


#: A reconstructor as a plugin would register it: no built-in code, its slope compiled in.
PLUGIN_SLOPE = Reconstructor("plugin-minmod", "minmod as a plugin", limiters.slope_minmod, 2)


def test_savage_hutter_kernel_depends_on_its_own_files_only() -> None:
    """The NT kernel of Savage–Hutter covers the model's file and the compiled code it reaches,
    not the CLI, another model or the folder around them."""
    model = registry.models.get("savage-hutter")(phi=35.0, delta=30.0)
    wall = registry.boundaries.get("wall")
    builtin = registry.reconstructors.get("mc")
    bound = nt.scheme_bindings(model, builtin, wall.fill_left, wall.fill_right)
    files = {text.split("\0", 1)[0] for text in dependency_sources(bound) if "\0" in text}
    names = {Path(file).name for file in files}
    assert "savage_hutter.py" in names
    # The built-in reconstructors are the template's own import, not a binding.
    assert "limiters.py" not in names
    assert not names & {"cli.py", "burgers.py", "shallow_water.py", "io.py", "config.py"}
    bound = nt.scheme_bindings(model, PLUGIN_SLOPE, wall.fill_left, wall.fill_right)
    files = {text.split("\0", 1)[0] for text in dependency_sources(bound) if "\0" in text}
    assert "limiters.py" in {Path(file).name for file in files}


def test_generated_lines_are_the_template_lines() -> None:
    """Outside the binding block (and the redirected import of the NT kernels in the FT
    template), line i of every generated module is line i of its template."""
    model = registry.models.get("savage-hutter")(phi=35.0, delta=30.0)
    wall = registry.boundaries.get("wall")
    left, right = wall.fill_left, wall.fill_right
    mc = registry.reconstructors.get("mc")
    nt_module = nt.nt_kernels(model, mc, left, right)
    ft_module = ft_kernels(model, mc, left, right)
    arrays = model._compiled_arrays()
    conslaw_folder = Path(conslaw.__file__).parent
    cases = (
        (nt_module, nt.TEMPLATE),
        (ft_module, conslaw_folder / "schemes" / "front_tracking" / "kernel_template.py"),
        (arrays, conslaw_folder / "array_kernels_template.py"),
    )
    for module, template in cases:
        generated_lines = Path(module.__file__).read_text().splitlines()
        template_lines = template.read_text().splitlines()
        assert len(generated_lines) == len(template_lines), template
        inside = False
        pairs = zip(generated_lines, template_lines, strict=True)
        for number, (ours, theirs) in enumerate(pairs, 1):
            if theirs.startswith(codegen._BEGIN):
                inside = True
            if not inside and "conslaw.schemes.nessyahu_tadmor.kernel_template" not in theirs:
                assert ours == theirs, (template, number)
            if theirs.startswith(codegen._END):
                inside = False


def test_a_traceback_in_a_kernel_names_the_template_line(tmp_path: Path) -> None:
    """Run as Python (NUMBA_DISABLE_JIT), an error inside a generated kernel is reported at the
    template's own line number, with the template's text."""
    script = textwrap.dedent(
        """
        import numpy as np
        from conslaw import registry
        from conslaw.schemes.nessyahu_tadmor.kernels import nt_kernels
        model = registry.models.get("burgers")()
        outflow = registry.boundaries.get("outflow")
        left, right = outflow.fill_left, outflow.fill_right
        kernels = nt_kernels(model, registry.reconstructors.get("mc"), left, right)
        kernels.copy_cells(np.zeros((1, 4)), np.zeros((1, 4)), 10)
        """
    )
    environment = dict(os.environ, NUMBA_DISABLE_JIT="1", CONSLAW_CACHE_DIR=str(tmp_path))
    done = subprocess.run(
        [sys.executable, "-c", script], env=environment, capture_output=True, text=True
    )
    assert "IndexError" in done.stderr
    frames = [
        line
        for line in done.stderr.splitlines()
        if "conslaw_kernel_nessyahu_tadmor_kernel_template" in line
    ]
    assert frames, done.stderr
    number = int(frames[-1].split("line ")[1].split(",")[0])
    template = nt.TEMPLATE.read_text().splitlines()
    assert template[number - 1].strip() == "dst[v, col(i)] = src[v, col(i)]"


def test_threads_generate_one_module(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Four threads asking for the same kernel at once get the same module, and it works."""
    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(codegen, "_loaded", {})
    model = registry.models.get("burgers")()
    periodic = registry.boundaries.get("periodic")
    left, right = periodic.fill_left, periodic.fill_right
    minmod = registry.reconstructors.get("minmod")
    modules: list[object] = []
    errors: list[BaseException] = []

    def build() -> None:
        try:
            modules.append(nt.nt_kernels(model, minmod, left, right))
        except BaseException as error:
            errors.append(error)

    threads = [threading.Thread(target=build) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
    assert len({id(module) for module in modules}) == 1
    assert len(list(tmp_path.glob("conslaw_kernel_nessyahu_tadmor_kernel_template_*.py"))) == 1
    state = np.zeros((1, Grid(0.0, 1.0, 4).n_cells + 6))
    modules[0].copy_cells(state, state, 4)


def test_kernels_of_other_bindings_are_not_pruned(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """Front-tracking kernels of a built-in and a plugin reconstructor (the same template, other
    imported NT kernels) are two families: writing one leaves the other in place. Every
    built-in reconstructor shares one kernel module (the choice is made at run time)."""
    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(codegen, "_loaded", {})
    model = registry.models.get("shallow-water")()
    wall = registry.boundaries.get("wall")
    first = ft_kernels(model, registry.reconstructors.get("mc"), wall.fill_left, wall.fill_right)
    second = ft_kernels(model, PLUGIN_SLOPE, wall.fill_left, wall.fill_right)
    assert first.__name__ != second.__name__
    assert Path(first.__file__).exists() and Path(second.__file__).exists()
    assert len(list(tmp_path.glob("conslaw_kernel_front_tracking_*.py"))) == 2
    for name in ("none", "minmod", "superbee", "vanleer", "weno3", "weno5"):
        builtin = registry.reconstructors.get(name)
        again = ft_kernels(model, builtin, wall.fill_left, wall.fill_right)
        assert again is first, name


def test_a_first_compile_is_announced(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """With an empty kernel cache a scheme says that its kernels will be compiled, and after
    :meth:`compile` that they will not; a run tells its ``notice`` callback once, before the
    compile, and not at all when the kernels are cached."""
    from conftest import make_scheme

    from conslaw.config import load_scene
    from conslaw.simulation import simulate
    from conslaw.state import State

    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(codegen, "_loaded", {})
    scheme = make_scheme("burgers", "weno5", 16)
    assert scheme.needs_compile()
    state = State(0.0, scheme.grid.centres(), np.zeros((1, 16)), 0.0)
    scheme.compile(state)
    assert not scheme.needs_compile()
    assert not make_scheme("burgers", "minmod", 16).needs_compile()  # the same kernel
    scene = load_scene("burgers-sine", {"n_cells": 16, "t_end": 0.01})
    notices: list[str] = []
    simulate(scene, notice=notices.append)
    assert notices == []
    monkeypatch.setattr(type(scheme), "needs_compile", lambda self: True)
    simulate(scene, notice=notices.append)
    assert len(notices) == 1 and "compiling the nessyahu-tadmor kernels for burgers" in notices[0]


CHILD = """
import importlib, sys
import numpy as np
sys.path.insert(0, {source!r})
from conslaw.kernelgen import generate
physics = importlib.import_module("{name}.physics")
module = generate({template!r}, {{"_twice": physics.twice}}, {{"SCALE": 3.0}})
print(module.apply(np.array([1.0, 2.0])).tolist(), sum(module.apply.stats.cache_hits.values()))
"""


LOCKED_CHILD = """
import importlib, sys
import numpy as np
sys.path.insert(0, {source!r})
from conslaw.kernelgen import compile_lock, generate
physics = importlib.import_module("{name}.physics")
module = generate({template!r}, {{"_twice": physics.twice}}, {{"SCALE": 3.0}})
print("ready", flush=True)
with compile_lock(module):
    module.apply(np.array([1.0]))
print(sum(module.apply.stats.cache_hits.values()))
"""


def test_processes_that_need_the_same_kernels_compile_them_once(
    package: tuple[str, Path],
) -> None:
    """Two processes wait on the compile lock (held here) for the same cold module; released,
    one compiles it and the other loads it from the cache (one cache hit between them; without
    the lock both would compile at once)."""
    name, folder = package
    script = LOCKED_CHILD.format(
        source=str(folder.parent), name=name, template=str(folder / "template.py")
    )
    module = generated(name, folder)
    with codegen.compile_lock(module):  # type: ignore[arg-type]
        children = [
            subprocess.Popen(
                [sys.executable, "-c", script],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            )
            for _ in range(2)
        ]
        for child in children:
            assert child.stdout is not None and child.stdout.readline().strip() == "ready"
    outputs = [child.communicate() for child in children]
    assert all(child.returncode == 0 for child in children), outputs
    assert sorted(int(out.strip()) for out, _ in outputs) == [0, 1], outputs


def test_a_damaged_kernel_cache_is_rebuilt(package: tuple[str, Path], numba_cache: str) -> None:
    """Garbled numba index files, truncated data files and a generated module that is not
    UTF-8 (a crash or a full disk while they were written): the next process rebuilds them and
    gets the right numbers, and the process after it loads the rebuilt entries (numba's cache
    beside the module or under ``NUMBA_CACHE_DIR``)."""
    name, folder = package
    script = CHILD.format(
        source=str(folder.parent), name=name, template=str(folder / "template.py")
    )

    def child() -> tuple[list[float], int]:
        done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
        assert done.returncode == 0 and not done.stderr, done.stderr
        values, hits = done.stdout.rsplit(" ", 1)
        return json.loads(values), int(hits)

    assert child() == ([6.0, 12.0], 0)
    assert child() == ([6.0, 12.0], 1)
    cache = Path(os.environ["CONSLAW_CACHE_DIR"])
    numba_folder = codegen.numba_cache_folder(cache / "module.py")
    assert list(numba_folder.glob("*.nbi")), "the children's cache is not where it is looked for"
    for index in numba_folder.glob("*.nbi"):
        index.write_bytes(b"\x80garbled")
    for data in numba_folder.glob("*.nbc"):
        data.write_bytes(data.read_bytes()[:40])
    assert child() == ([6.0, 12.0], 0)
    assert child() == ([6.0, 12.0], 1)
    (module,) = cache.glob("conslaw_kernel_*.py")
    module.write_bytes(b"\xff\xfe not a module \x00")
    assert child()[0] == [6.0, 12.0]


def test_an_unusable_kernel_cache_folder_is_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """``CONSLAW_CACHE_DIR`` naming a file is reported (not silently replaced by another
    folder), and a module that cannot be written (a full disk) is one line too; exit 2."""
    from test_bad_input import run_in_process

    from conslaw.errors import KernelCacheError

    not_a_folder = tmp_path / "file"
    not_a_folder.write_text("")
    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(not_a_folder))
    monkeypatch.setattr(codegen, "_loaded", {})
    code, _, err = run_in_process(["run", "burgers-sine", "--no-plot", "--out", "x"], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert f"CONSLAW_CACHE_DIR='{not_a_folder}'" in lines[0], lines[0]
    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path / "kernels"))

    def full(source: object, target: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(codegen.os, "replace", full)
    with pytest.raises(KernelCacheError, match="No space left on device; free some space"):
        nt.nt_kernels(
            registry.models.get("burgers")(),
            registry.reconstructors.get("mc"),
            registry.boundaries.get("periodic").fill_left,
            registry.boundaries.get("periodic").fill_right,
        )


def test_warm_compiles_each_kernel_family_once(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``conslaw warm`` with two scenes of one kernel family compiles it once (in a worker
    process); then runs need no compile, and a second warm has nothing to do."""
    from test_bad_input import run_in_process

    from conslaw.config import load_scene
    from conslaw.simulation import build

    monkeypatch.setenv("CONSLAW_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(codegen, "_loaded", {})
    code, out, err = run_in_process(["warm", "burgers-sine", "burgers-riemann"], capsys)
    assert code == 0, err
    assert "compiling 1 kernel families" in out and "nessyahu-tadmor kernels for burgers" in out
    monkeypatch.setattr(codegen, "_loaded", {})
    _, _, scheme, _, _ = build(load_scene("burgers-riemann"))
    assert not scheme.needs_compile()
    code, out, err = run_in_process(["warm", "burgers-sine", "--jobs", "1"], capsys)
    assert code == 0 and "compiled already" in out, out + err
