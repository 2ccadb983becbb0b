"""Scene files: defaults, overrides, validation."""

from __future__ import annotations

import dataclasses

import pytest

import conslaw
from conslaw.config import load_scene, parse_value
from conslaw.errors import ConfigError


def test_defaults_fill_what_a_scene_does_not_name() -> None:
    scene = load_scene("burgers-sine")
    assert scene.scheme == "nessyahu-tadmor"
    assert scene.cfl == 0.45
    assert scene.output_times == (0.25,)
    assert scene.left.kind == "periodic"


def test_overrides_flat_and_dotted() -> None:
    scene = load_scene(
        "burgers-riemann", {"n_cells": 64, "boundary.left": "wall", "output_times": [0.2]}
    )
    assert scene.n_cells == 64 and scene.left.kind == "wall" and scene.right.kind == "outflow"
    assert scene.output_times == (0.2, 1.0)


def test_python_run_accepts_overrides_and_writes_nothing_without_out(tmp_path) -> None:  # type: ignore[no-untyped-def]
    result = conslaw.run("burgers-sine", n_cells=32, reconstructor="minmod")
    assert result.final.t == 0.25 and result.final.q.shape == (1, 32)
    assert result.files == []
    assert abs(result.mass_drift[0]) < 1e-13


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("800", 800),
        ("0.3", 0.3),
        ("true", True),
        ("weno5", "weno5"),
        ("[1, 2]", [1, 2]),
        ('"a b"', "a b"),
    ],
)
def test_parse_value(text: str, value: object) -> None:
    assert parse_value(text) == value


@pytest.mark.parametrize(
    ("overrides", "fragment"),
    [
        ({"output_times": [2.0]}, "output_times"),
        ({"t_end": -1.0}, "t_end"),
        ({"exact": "yes"}, "exact"),
        ({"output.formats": ["vtk"]}, "output.formats"),
        ({"output.colour": "red"}, "unknown key in [output]"),
        ({"boundary.left": {"kind": "inflow"}}, "state"),
        ({"boundary.left": {"kind": "outflow", "state": [1.0]}}, "takes no options"),
        ({"initial.breakpoints": [1.0, 0.0]}, "increasing"),
        ({"initial.states": [1.0, 2.0]}, "3 entries"),
        ({"description": 5}, "description"),
    ],
)
def test_invalid_scenes_are_config_errors(overrides: dict[str, object], fragment: str) -> None:
    with pytest.raises(ConfigError, match=fragment.replace("[", r"\[").replace(".", r"\.")):
        conslaw.run("burgers-riemann", **{k.replace(".", "__"): v for k, v in overrides.items()})


@pytest.mark.parametrize(
    ("scene", "overrides", "reason"),
    [
        ("burgers-riemann", {"t_end": 3.0}, "interact at t=2"),
        (
            "burgers-riemann",
            {"boundary__left": "periodic", "boundary__right": "periodic"},
            "outflow",
        ),
        ("burgers-sine", {"t_end": 0.5}, "breaks"),
        ("dam-break-wet", {"t_end": 8.0}, "reaches the boundary"),
        ("dam-break-wet", {"boundary__left": "wall"}, "outflow"),
        ("sh-similarity", {"initial__thin_layer": 0.5}, "thin layer"),
        ("sh-at-rest", {"exact": True, "t_end": 1.0}, "rear margin would move upslope"),
    ],
)
def test_exact_comparison_only_where_it_applies(
    scene: str, overrides: dict[str, object], reason: str
) -> None:
    """No error against an exact solution that does not apply; the reason is reported."""
    result = conslaw.run(scene, n_cells=40, **overrides)
    assert result.exact_solution is None and result.errors[-1] is None
    assert result.exact_note is not None and reason in result.exact_note


def test_front_tracking_is_a_scheme_and_the_old_flag_still_chooses_it() -> None:
    """``scheme = "front-tracking"`` and the flag of earlier scene files (``front_tracking =
    true`` with nessyahu-tadmor) give the same scene; the flag with another scheme is refused
    in one line naming what to write."""
    by_name = load_scene("sh-similarity", {"scheme": "front-tracking", "exact": False})
    by_flag = load_scene("sh-similarity", {"front_tracking": True, "exact": False})
    # Alike but for the description, which names the overrides.
    assert dataclasses.replace(by_name, description="") == dataclasses.replace(
        by_flag, description=""
    )
    assert by_flag.scheme == "front-tracking" and by_flag.front_tracking
    assert load_scene("sh-similarity").front_tracking is False
    with pytest.raises(ConfigError, match='scheme = "front-tracking"'):
        load_scene("sh-similarity", {"front_tracking": True, "scheme": "lagrangian"})
    written = by_flag.to_table()
    assert written["scheme"] == "front-tracking" and "front_tracking" not in written
    # The resolved scene names the scheme alone, so choosing another scheme is one override.
    assert load_scene("sh-similarity-ft", {"scheme": "nessyahu-tadmor"}).front_tracking is False
    with pytest.raises(ConfigError, match="false contradicts"):
        load_scene("sh-similarity-ft", {"front_tracking": False})


def test_a_scene_replaced_with_the_flag_runs_front_tracking() -> None:
    """A Scene object given ``front_tracking=True`` by ``dataclasses.replace`` (the flag of
    earlier versions) runs the front-tracking scheme: its states carry margins."""
    import dataclasses

    from conslaw.simulation import build

    scene = load_scene("sh-similarity-ft", {"scheme": "nessyahu-tadmor", "exact": False})
    assert not scene.front_tracking
    _, _, scheme, initial, _ = build(dataclasses.replace(scene, front_tracking=True))
    assert scheme.name == "front-tracking" and initial.margins is not None
    with pytest.raises(ConfigError, match="contradicts"):
        build(dataclasses.replace(load_scene("sh-similarity-ft"), front_tracking=False))


@pytest.mark.parametrize(
    ("interval", "t_end", "times"),
    [
        (0.1, 1.0, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]),
        (0.3, 1.0, [0.0, 0.3, 0.6, 0.9, 1.0]),
        (1.0 / 3.0, 1.0, [0.0, 0.333333333333, 0.666666666667, 1.0]),
        (5.0, 2.0, [0.0, 2.0]),
    ],
)
def test_an_output_interval_adds_evenly_spaced_times(
    interval: float, t_end: float, times: list[float]
) -> None:
    scene = load_scene("burgers-sine", {"output_interval": interval, "t_end": t_end})
    assert list(scene.output_times) == times


def test_an_output_interval_merges_with_the_listed_times() -> None:
    scene = load_scene(
        "burgers-sine", {"output_interval": 0.1, "t_end": 0.3, "output_times": [0.15]}
    )
    assert list(scene.output_times) == [0.0, 0.1, 0.15, 0.2, 0.3]


def test_a_run_builds_its_model_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """Validation builds the model (it checks its own parameters) and the run uses that one;
    a scene given other parameters with ``dataclasses.replace`` gets a model of its own."""
    from conslaw import registry
    from conslaw.simulation import simulate

    model_class = registry.models.get("shallow-water")
    built: list[dict[str, float]] = []
    original = model_class.__init__

    def counting(self: object, **parameters: float) -> None:
        built.append(parameters)
        original(self, **parameters)  # type: ignore[arg-type]

    monkeypatch.setattr(model_class, "__init__", counting)
    scene = load_scene("dam-break-wet", {"n_cells": 20, "t_end": 0.05})
    simulate(scene)
    simulate(dataclasses.replace(scene, n_cells=30))
    assert built == [{"g": 1.0}]
    other = dataclasses.replace(scene, parameters={"g": 2.0})
    assert other.model_instance().params.g == 2.0  # type: ignore[attr-defined]
    assert built == [{"g": 1.0}, {"g": 2.0}]


def test_numbers_from_numpy_are_taken_as_python_numbers() -> None:
    """A scene given from Python with numpy scalars and arrays (a loop over ``np.linspace``)
    holds Python numbers, writes as TOML and runs: before, a numpy friction angle made the
    model's flags numpy bools, which the generated kernel module could not name."""
    import numpy as np
    import tomli_w

    from conslaw.scene2d import load_any_scene

    overrides = {
        "parameters.delta": np.float64(25.0), "n_cells": np.int64(100),
        "cfl": np.float32(0.25), "output_times": np.linspace(0.0, 10.0, 3),
        "parameters.phi": np.float64(30.0),
    }  # fmt: skip
    scene = load_scene("sh-runout-shock", overrides)
    assert type(scene.parameters["delta"]) is float and type(scene.n_cells) is int
    assert scene.cfl == 0.25 and scene.output_times == (0.0, 5.0, 10.0, 20.0)
    assert all(type(t) is float for t in scene.output_times)
    tomli_w.dumps(scene.to_table())
    result = conslaw.simulate(dataclasses.replace(scene, t_end=1.0, output_times=(1.0,)))
    assert result.final.t == 1.0
    two = load_any_scene("sh2d-similarity", {"parameters.delta": np.float64(0.0)})
    assert type(two.parameters["delta"]) is float


def test_kernel_constants_are_written_as_python_literals() -> None:
    import numpy as np

    from conslaw.kernelgen.generation import _literal

    assert [_literal(v) for v in (np.True_, np.False_, True, np.int64(3), 7)] == [
        "True", "False", "True", "3", "7",
    ]  # fmt: skip
    assert _literal(np.float32(0.5)) == "0.5" and _literal(np.float64(1e-3)) == "0.001"
    with pytest.raises(TypeError, match="kernel constant"):
        _literal("yes")


def test_numpy_dates_and_namedtuples_keep_their_meaning() -> None:
    """A numpy date is not a number, and a namedtuple stays a tuple: both refused by the
    validation in one line naming the key (not a TypeError from rebuilding the namedtuple)."""
    from collections import namedtuple

    import numpy as np

    with pytest.raises(ConfigError, match="n_cells"):
        load_scene("burgers-sine", {"n_cells": np.datetime64(200, "ns")})
    Times = namedtuple("Times", "first second")
    with pytest.raises(ConfigError, match="output_times"):
        load_scene("burgers-sine", {"output_times": Times(0.1, np.float64(0.2))})
