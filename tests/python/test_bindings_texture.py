"""The Python bindings' texture, BEM and film layers, against closed forms
(sine profile MPD, Hertz contact) and known synthetic inputs."""

import math
import os
from pathlib import Path

import numpy as np
import pytest

# Skipped where the bindings are not installed, except in CI
# (TYREROAD_REQUIRE_BINDINGS=1), where a missing module must fail, not skip.
if os.environ.get("TYREROAD_REQUIRE_BINDINGS") == "1":
    import tyreroad as tr
else:
    tr = pytest.importorskip("tyreroad")

ROOT = Path(__file__).resolve().parents[2]
RUBBER = tr.Material(6.54e6, 0.5)


def sine_map(amplitude=1e-3, wavelength=0.01, nx=1000, ny=4, dx=1e-4):
    x = np.arange(nx) * dx
    row = amplitude * np.sin(2 * np.pi * x / wavelength)
    return np.ascontiguousarray(np.tile(row, (ny, 1))), dx


# --- textures ----------------------------------------------------------------


def test_npz_round_trip_is_exact(tmp_path):
    h, dx = sine_map()
    path = tmp_path / "sine.npz"
    np.savez(path, heights=h, spacing=[dx, 2 * dx])
    heights, rdx, rdy = tr.read_texture(path)
    assert (rdx, rdy) == (dx, 2 * dx)
    np.testing.assert_array_equal(heights, h)


def test_every_fixture_format_reads(tmp_path):
    for name in ["sine.asc", "spheres.x3p"]:
        heights, dx, dy = tr.read_texture(ROOT / "fixtures" / "texture" / name)
        assert heights.ndim == 2 and heights.dtype == np.float64
        assert dx > 0 and dy > 0 and np.isfinite(heights).any()
    with pytest.raises(tr.TextureError):
        tr.read_texture(tmp_path / "missing.x3p")


def test_mpd_of_a_cosine_is_its_sampled_amplitude():
    # h_i = A cos(2 pi (i + 1/2) dx / lambda) is symmetric about each 50 mm
    # half-segment's centre: the regression line is flat at zero and the
    # sampled peaks are A cos(pi dx / lambda), so MPD is that exactly.
    a, lam, dx = 0.7e-3, 12.5e-3, 0.5e-3
    x = (np.arange(1000) + 0.5) * dx
    h = np.ascontiguousarray(np.tile(a * np.cos(2 * np.pi * x / lam), (3, 1)))
    m = tr.mean_profile_depth(h, dx, 1e-3)
    assert m["mpd"] == pytest.approx(a * math.cos(math.pi * dx / lam), rel=1e-12)
    assert (m["samples"], m["segments"]) == (200, 15)
    assert m["baseline"] == pytest.approx(0.1)


def test_texture_spectrum_peaks_in_the_sine_band():
    wavelength = 0.01  # 10 mm: a band centre (index 10)
    h, dx = sine_map(amplitude=1e-3, wavelength=wavelength, nx=2000)
    s = tr.texture_spectrum(h, dx, dx)
    k = int(np.argmax(s["level_db"]))
    assert s["lower"][k] <= wavelength <= s["upper"][k]
    rms = 1e-3 / math.sqrt(2)
    assert s["rms"][k] == pytest.approx(rms, rel=0.15)


def bumps(nx=200, ny=160, dx=1e-4, radius=4e-3):
    x = np.arange(nx) * dx
    y = np.arange(ny) * dx
    xx, yy = np.meshgrid(x, y)
    centres = [(0.005, 0.008), (0.014, 0.007)]
    h = np.full((ny, nx), -1e-3)
    for cx, cy in centres:
        r2 = (xx - cx) ** 2 + (yy - cy) ** 2
        h = np.maximum(h, -r2 / (2 * radius))
    return np.ascontiguousarray(h), dx, centres


def test_segmentation_finds_the_bumps_and_their_radii():
    h, dx, centres = bumps()
    seg = tr.segment(h, dx, dx, min_prominence=1e-4)
    assert len(seg["x"]) == 2
    found = sorted(zip(seg["x"], seg["y"]))
    for (x, y), (cx, cy) in zip(found, sorted(centres)):
        assert abs(x - cx) <= dx and abs(y - cy) <= dx
    np.testing.assert_allclose(seg["radius_x"], 4e-3, rtol=0.05)
    np.testing.assert_allclose(seg["radius_y"], 4e-3, rtol=0.05)
    assert seg["labels"].shape == h.shape and seg["labels"].dtype == np.uint32


def test_self_affine_has_the_requested_rms_and_is_reproducible():
    a, dx, dy = tr.self_affine(128, 64, 1e-4, 1e-4, 2e-4, 0.8, 5e-3, 5e-4, seed=7)
    b, _, _ = tr.self_affine(128, 64, 1e-4, 1e-4, 2e-4, 0.8, 5e-3, 5e-4, seed=7)
    assert a.shape == (64, 128) and (dx, dy) == (1e-4, 1e-4)
    np.testing.assert_array_equal(a, b)
    assert np.sqrt(np.mean((a - a.mean()) ** 2)) == pytest.approx(2e-4, rel=1e-9)
    with pytest.raises(tr.TextureError):
        tr.self_affine(128, 64, 1e-4, 1e-4, 2e-4, 1.5, 5e-3, 5e-4)


class FakeTopography:
    """What SurfaceTopography's Topography offers: heights()[x, y], sizes."""

    def __init__(self, h_xy, sizes):
        self._h = h_xy
        self.physical_sizes = sizes

    def heights(self):
        return self._h


def test_topography_objects_are_taken_transposed():
    h, dx = sine_map(nx=1000, ny=6)
    topo = FakeTopography(h.T, (1000 * dx, 6 * 2 * dx))
    heights, tdx, tdy = tr.height_map(topo)
    np.testing.assert_array_equal(heights, h)
    assert (tdx, tdy) == pytest.approx((dx, 2 * dx))
    same = tr.mean_profile_depth(*tr.height_map(topo))
    assert same["mpd"] == tr.mean_profile_depth(h, dx, 2 * dx)["mpd"]
    view, _, _ = tr.height_map(h, dx)
    assert view is h  # a plain array passes through: no copy


def test_texture_input_is_checked():
    h, dx = sine_map()
    with pytest.raises(tr.InputError, match="float64"):
        tr.mean_profile_depth(h.astype(np.float32), dx, dx)
    with pytest.raises(tr.InputError, match="contiguous"):
        tr.mean_profile_depth(h[:, ::2], dx, dx)
    with pytest.raises(tr.InputError, match="2-D"):
        tr.mean_profile_depth(h[0], dx, dx)
    with pytest.raises(tr.TextureError):
        tr.mean_profile_depth(np.full((4, 1000), np.nan), dx, dx)
    with pytest.raises(tr.TextureError):
        tr.segment(h, -dx, dx, 1e-4)


# --- BEM ---------------------------------------------------------------------


def test_bem_sphere_matches_hertz():
    n, dx, radius, load = 96, 2.5e-5, 5e-3, 5.0
    c = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(c, c)
    h = np.ascontiguousarray(-(xx**2 + yy**2) / (2 * radius))
    out = tr.bem_solve(h, dx, dx, RUBBER, load=load)
    assert out["force"] == pytest.approx(load, rel=1e-6)
    a = (3 * load * radius / (4 * RUBBER.reduced_modulus)) ** (1 / 3)
    assert out["contact_area"] == pytest.approx(np.pi * a**2, rel=0.05)
    assert out["pressure"].shape == (n, n)
    assert out["pressure"].sum() * dx * dx == pytest.approx(load, rel=1e-6)
    p0 = 3 * load / (2 * np.pi * a**2)
    assert out["pressure"].max() == pytest.approx(p0, rel=0.05)


def test_bem_refuses_nan_and_conflicting_controls():
    h = np.zeros((8, 8))
    h[3, 3] = np.nan
    with pytest.raises(tr.Error):
        tr.bem_solve(h, 1e-4, 1e-4, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match="exactly one"):
        tr.bem_solve(np.zeros((8, 8)), 1e-4, 1e-4, RUBBER)


# --- film --------------------------------------------------------------------


def test_film_prints_are_found_with_their_areas():
    size, px = 200, 1e-4
    yy, xx = np.mgrid[0:size, 0:size]
    grey = np.full((size, size), 0.95)
    discs = [(50, 60, 15), (140, 120, 20)]
    for cx, cy, r in discs:
        grey[(xx - cx) ** 2 + (yy - cy) ** 2 <= r * r] = 0.5
    out = tr.analyse_film(grey, px)
    assert len(out["area"]) == 2
    areas = sorted(out["area"])
    expected = sorted(np.pi * (r * px) ** 2 for _, _, r in discs)
    np.testing.assert_allclose(areas, expected, rtol=0.05)
    assert np.all(out["mean_pressure"] > 0)
    np.testing.assert_allclose(out["force"], out["mean_pressure"] * out["area"], rtol=1e-12)
    assert out["labels"].shape == grey.shape


def test_film_input_is_checked():
    grey = np.full((50, 50), 0.9)
    with pytest.raises(tr.InputError, match="outside"):
        tr.analyse_film(grey * 2, 1e-4)
    with pytest.raises(tr.InputError, match="curve"):
        tr.analyse_film(grey, 1e-4, curve="Z")
    with pytest.raises(tr.FilmError):
        tr.analyse_film(grey, -1e-4)


# --- two-scale pressure maps of a texture scenario ----------------------------


def test_texture_scenario_pressure_maps_carry_the_loads():
    r = tr.run_scenario(ROOT / "fixtures" / "texture_block_static.toml")
    assert r["kind"] == "texture" and r["segmented"] > 0
    np.testing.assert_allclose(r["total_force"], r["loads"], rtol=1e-10)
    for load, m in zip(r["loads"], r["pressure_maps"]):
        dx, dy = m["spacing"]
        assert np.all(m["pressure"] >= 0)
        # Conservation: the rebuilt local fields carry the solved forces.
        assert m["pressure"].sum() * dx * dy == pytest.approx(load, rel=1e-9)
        np.testing.assert_allclose(r["forces"][list(r["loads"]).index(load)].sum(), load, rtol=1e-10)
    # The Wilke rung calibrates nothing, so nothing fell back.
    assert r["calibration_fallbacks"] == []


def test_a_calibrated_texture_scenario_lists_no_fallback_when_every_cap_calibrates():
    text = (ROOT / "fixtures" / "texture_block_static.toml").read_text()
    text = text.replace("[material]", '[model]\nfidelity = "calibrated"\n\n[material]', 1)
    r = tr.run_scenario(text, base_dir=ROOT / "fixtures")
    assert r["kind"] == "texture" and r["calibration_fallbacks"] == []
    np.testing.assert_allclose(r["total_force"], r["loads"], rtol=1e-9)
