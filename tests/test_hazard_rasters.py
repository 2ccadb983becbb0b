"""The hazard rasters as a GIS reads them (docs/output.md, "Hazard maps"): float32, a value
only where the flow reached (the ``reached`` cells of ``hazard_maps``, the deposit where flow is
left) and the declared no-data value elsewhere, the DEM's CRS or a printed note that there is
none; and the run saying what its states hold."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import rasterio

import conslaw
from conslaw.cli import main
from conslaw.peak_fields import REACHED_DEPTH
from conslaw.result2d import RunResult2D
from conslaw.terrain import dem_from_function, write_dem
from conslaw.terrain.hazard_maps import NODATA, hazard_maps

UTM = "EPSG:32632"
X0, Y0 = 500000.0, 5200000.0
STEMS = ("peak_depth", "peak_speed", "peak_pressure", "deposit")
SMALL = ["--set", "n_cells=[40, 20]", "--set", "t_end=20.0", "--set", "output_times=[20.0]"]


def geotiff(path: Path) -> tuple[dict[str, object], np.ma.MaskedArray]:
    """``(profile, band 1 masked where no data)`` of a GeoTIFF, rows from the south."""
    with rasterio.open(path) as dataset:
        return dict(dataset.profile), dataset.read(1, masked=True)[::-1]


@pytest.fixture(scope="module")
def layered(tmp_path_factory: pytest.TempPathFactory) -> tuple[RunResult2D, Path]:
    """``terrain-plane-to-flat`` on 25 m cells over a layer of 2 cm everywhere: a cell is
    reached at 3 cm, not at the 1 cm of the layer alone."""
    out = tmp_path_factory.mktemp("layered")
    result = conslaw.run_2d(
        "terrain-plane-to-flat",
        out=out,
        n_cells=[40, 20],
        output_times=[20.0, 60.0],
        initial__thin_layer=0.02,
    )
    return result, out


def test_the_rasters_hold_values_only_where_the_flow_reached(
    layered: tuple[RunResult2D, Path],
) -> None:
    """Every hazard GeoTIFF is float32 with the no-data value -9999 declared; its valid cells
    are exactly the reached cells (peak flow depth at least REACHED_DEPTH above the layer that
    covered the domain at the start, computed here from the run's peak fields), the deposit's
    those where the final flow depth is; the values there are the run's, in float32."""
    result, out = layered
    assert result.peaks is not None
    depth_now = result.model.flow_depth_and_speed
    layer = float(np.min(depth_now(result.initial.q, result.peaks.aux)[0]))
    assert layer == pytest.approx(0.02)
    reached = result.peaks.depth >= layer + REACHED_DEPTH
    final_depth = depth_now(result.final.q, result.peaks.aux)[0]
    left = final_depth >= layer + REACHED_DEPTH
    assert 0 < np.count_nonzero(left) < np.count_nonzero(reached) < reached.size
    assert np.all(result.peaks.depth >= REACHED_DEPTH)  # a plain 1 cm rule would keep them all
    maps = hazard_maps(result)
    assert maps is not None
    np.testing.assert_array_equal(maps.reached, reached)
    summary = json.loads((out / "hazard.json").read_text())
    assert summary["reached_cells"] == np.count_nonzero(reached)
    assert summary["geotiff_nodata"] == NODATA == -9999.0 and summary["crs"] is None
    values = {field.stem: field.values for field in maps.fields}
    for stem in STEMS:
        profile, band = geotiff(out / f"{stem}.tif")
        assert profile["dtype"] == "float32" and profile["nodata"] == NODATA
        valid = left if stem == "deposit" else reached
        np.testing.assert_array_equal(~np.ma.getmaskarray(band), valid)
        np.testing.assert_array_equal(band.data[~valid], np.float32(NODATA))
        np.testing.assert_array_equal(band.compressed(), values[stem][valid].astype(np.float32))
    np.testing.assert_array_equal(values["peak_depth"], result.peaks.depth)
    np.testing.assert_array_equal(values["deposit"], final_depth)


def dem_file(folder: Path, crs: str | None) -> Path:
    """A 400 m x 200 m DEM of 10 m cells descending at 35 degrees toward the east."""
    slope = math.tan(math.radians(35.0))
    dem = dem_from_function(
        lambda x, y: 1000.0 - slope * (x - X0) + 0.0 * y,
        (X0, X0 + 400.0),
        (Y0, Y0 + 200.0),
        10.0,
        crs,
    )
    return write_dem(dem, folder / "slope.tif")


def dem_run(folder: Path, crs: str | None, capsys: pytest.CaptureFixture[str]) -> str:
    """``conslaw run`` of a square release on :func:`dem_file` for 6 s; what it printed."""
    dem_file(folder, crs)
    scene = folder / "scene.toml"
    square = [[X0 + 50, Y0 + 70], [X0 + 110, Y0 + 70], [X0 + 110, Y0 + 130], [X0 + 50, Y0 + 130]]
    scene.write_text(
        f"""model = "savage-hutter-terrain"
n_cells = [40, 20]
x_min = {X0}
x_max = {X0 + 400.0}
y_min = {Y0}
y_max = {Y0 + 200.0}
t_end = 6.0
output_times = [6.0]
exact = false

[parameters]
phi = 35.0
delta = 25.0
terrain = "dem"
dem_file = "slope.tif"

[initial]
kind = "release"
thickness = 2.0
polygon = {square}

[output]
formats = ["npz", "geotiff"]
plot = false
"""
    )
    code = main(["run", str(scene), "--out", str(folder / "run")])
    assert code == 0
    return capsys.readouterr().out


def test_a_dem_with_a_crs_gives_it_to_the_rasters(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A DEM file in UTM 32N: every hazard GeoTIFF carries its CRS and transform, and the run
    prints what the states hold but no note about a missing CRS."""
    printed = dem_run(tmp_path, UTM, capsys)
    with rasterio.open(tmp_path / "slope.tif") as dem:
        crs, transform = dem.crs, dem.transform
    for stem in STEMS:
        profile, band = geotiff(tmp_path / "run" / f"{stem}.tif")
        assert profile["crs"] == crs and profile["crs"].to_string() == UTM
        assert profile["transform"] == transform and profile["dtype"] == "float32"
        assert band.count() > 0 and np.ma.getmaskarray(band).any()
    assert "note: the states' h (states.npz q[:, 0]) is the volume per map area H" in printed
    assert "CRS" not in printed


def test_a_dem_without_a_crs_is_noted_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A DEM file without a CRS: the run prints one line saying the GeoTIFFs carry none and
    why (not an error: the run ends with 0 and writes them, without a CRS)."""
    printed = dem_run(tmp_path, None, capsys)
    lines = [line for line in printed.splitlines() if "CRS" in line]
    assert lines == [
        f"  note: the hazard GeoTIFFs carry no CRS (DEM file '{tmp_path / 'slope.tif'}' has "
        "none): a GIS takes their coordinates as metres in an unknown projection"
    ]
    profile, _ = geotiff(tmp_path / "run" / "peak_depth.tif")
    assert profile["crs"] is None


def test_a_terrain_formula_is_noted_and_without_geotiffs_nothing_is_said(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``terrain-plane-to-flat`` (a formula) prints the note; asked for no GeoTIFFs, it does
    not (there is nothing to carry a CRS)."""
    assert main(["run", "terrain-plane-to-flat", "--out", str(tmp_path / "a"), *SMALL]) == 0
    printed = capsys.readouterr().out
    assert "  note: the hazard GeoTIFFs carry no CRS (a terrain formula has none)" in printed
    no_tif = [*SMALL, "--set", 'output.formats=["npz"]', "--no-plot"]
    assert main(["run", "terrain-plane-to-flat", "--out", str(tmp_path / "b"), *no_tif]) == 0
    printed = capsys.readouterr().out
    assert "CRS" not in printed and "volume per map area H" in printed
    assert not list((tmp_path / "b").glob("*.tif"))


def test_the_map_figures_show_the_cells_the_rasters_hold(
    layered: tuple[RunResult2D, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each hazard PNG draws its field on exactly the cells its GeoTIFF holds (over a layer
    of 2 cm the reached cells are those 1 cm above it, not every cell 1 cm deep), with the
    run's values there and nothing elsewhere."""
    import conslaw.plotting2d as plotting2d

    result, out = layered
    drawn: list[np.ndarray] = []
    draw = plotting2d.hazard_map_figure

    def recorded(dem: object, values: np.ndarray, **options: object) -> object:
        drawn.append(np.array(values))
        return draw(dem, values, **options)  # type: ignore[arg-type]

    monkeypatch.setattr(plotting2d, "hazard_map_figure", recorded)
    plotting2d.write_figures_2d(result, tmp_path)
    assert len(drawn) == len(STEMS)
    for stem, values in zip(STEMS, drawn, strict=True):
        _, band = geotiff(out / f"{stem}.tif")
        valid = ~np.ma.getmaskarray(band)
        np.testing.assert_array_equal(values != 0.0, valid & (band.filled(0.0) != 0.0))
        np.testing.assert_array_equal(values[~valid], 0.0)
        np.testing.assert_array_equal(values[valid].astype(np.float32), band.compressed())
