"""The .npz outputs of `cargo xtask run`, opened by numpy.

Runs the runner (through `cargo xtask`, as a user would) on a small rolling
scenario (fixtures/rolling_small.toml) and on a small static texture scenario
written here, into temporary folders, then checks the numbers the arrays hold
against the CSV tables beside them and against the scenarios:

- steps.npz: the contact forces summed per step give time_signals.csv's
  total_force_n (1e-9 relative); the dense steps x asperities matrix and the
  contact positions relative to the footprint, built as README.md and
  docs/rolling.md say;
- the two-scale pressure maps integrate to their load (1e-6 relative);
- the height map has the scenario's shape and spacing.

Run from the repository root: `python -m pytest tests/python -q` (CI: .ci/run).
"""

import csv
import os
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]

# A flat block on 20 x 20 mm of synthetic 4/6 chippings: the texture path of
# fixtures/texture_block_static.toml at a quarter of its area, so the test
# takes seconds.
TEXTURE_SMALL = """
name = "texture_small"
description = "Flat block on 20 x 20 mm of synthetic 4/6 aggregate"

[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5

[static]
loads = ["20 N", "40 N"]

[texture]
min_prominence = "0.2 mm"
min_area = "2 mm2"
constant = 0.36

[texture.synth]
kind = "aggregate"
nx = 200
ny = 160
spacing = "0.1 mm"
grading = "4/6"
seed = 2026
"""

UNITS = {"mm": 1e-3, "m": 1.0, "N": 1.0, "km/h": 1 / 3.6, "m/s": 1.0}


def quantity(text: str) -> float:
    """A scenario quantity such as "0.1 mm" or "50 N" in SI units."""
    value, unit = text.split()
    return float(value) * UNITS[unit]


def xtask_run(scenario: Path, out: Path) -> None:
    """`cargo xtask run SCENARIO --out OUT` from the repository root.

    With TYREROAD_XTASK set (CI: the binary that `cargo test --workspace`
    has just built), that executable instead of `cargo xtask`, which would
    build the whole workspace once more in the dev profile.
    """
    xtask = os.environ.get("TYREROAD_XTASK")
    runner = [xtask] if xtask else ["cargo", "xtask"]
    done = subprocess.run(
        [*runner, "run", str(scenario), "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, (
        f"cargo xtask run {scenario} failed ({done.returncode}):\n"
        f"{done.stdout}\n{done.stderr}"
    )


def read_csv(path: Path) -> dict[str, np.ndarray]:
    """A CSV table's columns as float arrays, by header name (text columns,
    such as time_signals.csv's status and recovery, as string arrays)."""
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows, f"{path} has no rows"

    def column(k: str) -> np.ndarray:
        try:
            return np.array([float(r[k]) for r in rows])
        except ValueError:
            return np.array([r[k] for r in rows])

    return {k: column(k) for k in rows[0]}


@pytest.fixture(scope="module")
def rolling_out(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("rolling_small")
    xtask_run(ROOT / "fixtures" / "rolling_small.toml", out)
    return out


@pytest.fixture(scope="module")
def texture_run(tmp_path_factory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("texture_small")
    scenario = out / "texture_small.toml"
    scenario.write_text(TEXTURE_SMALL)
    xtask_run(scenario, out)
    return out, tomllib.loads(TEXTURE_SMALL)


def test_rolling_steps_npz_matches_time_signals(rolling_out: Path) -> None:
    spec = tomllib.loads((ROOT / "fixtures" / "rolling_small.toml").read_text())
    rolling = spec["rolling"]
    signals = read_csv(rolling_out / "time_signals.csv")
    road = np.load(rolling_out / "road.npz")
    steps = np.load(rolling_out / "steps.npz")
    assert set(steps.files) == {
        "time", "position", "lateral", "step", "asperity", "force", "status"
    }
    n_steps = steps["time"].size
    # Every step converged: status 0 in steps.npz, "converged" in the CSV.
    assert steps["status"].dtype == np.int64 and (steps["status"] == 0).all()
    assert (signals["status"] == "converged").all()
    n_road = road["ids"].size
    assert n_steps == 40 == signals["time_s"].size
    assert steps["position"].shape == (n_steps,)
    np.testing.assert_allclose(steps["time"], signals["time_s"], rtol=1e-9)
    np.testing.assert_allclose(steps["position"], signals["position_m"], rtol=1e-9)
    start, dx = quantity(rolling["start"]), quantity(rolling["step"])
    np.testing.assert_allclose(steps["position"], start + dx * np.arange(n_steps), rtol=1e-12)
    assert steps["lateral"].shape == ()
    assert steps["lateral"] == pytest.approx(quantity(rolling["lateral"]), rel=1e-12)

    step, asperity, force = steps["step"], steps["asperity"], steps["force"]
    assert (step.dtype, asperity.dtype, force.dtype) == (np.int64, np.int64, np.float64)
    assert step.shape == asperity.shape == force.shape
    assert force.size > n_steps, "a tyre has several contacts at each step"
    assert np.all(force > 0.0), "only contacts are recorded"
    assert step.min() >= 0 and step.max() < n_steps
    assert asperity.min() >= 0 and asperity.max() < n_road
    assert np.unique(step * n_road + asperity).size == force.size, "one triplet per contact"

    # Σ P_i per step is the total force, and the count the number of contacts.
    per_step = np.bincount(step, weights=force, minlength=n_steps)
    np.testing.assert_allclose(per_step, signals["total_force_n"], rtol=1e-9, atol=0.0)
    np.testing.assert_array_equal(np.bincount(step, minlength=n_steps), signals["n_contacts"])
    assert per_step == pytest.approx(np.full(n_steps, quantity(rolling["control"]["load"])), rel=1e-9)

    # The dense steps x asperities matrix, in the one line the docs give.
    s, r = steps, road
    n = r["ids"].size
    F = np.bincount(s["step"] * n + s["asperity"], s["force"], s["time"].size * n).reshape(-1, n)
    assert F.shape == (n_steps, n_road)
    np.testing.assert_allclose(F.sum(axis=1), signals["total_force_n"], rtol=1e-9)
    assert np.count_nonzero(F) == force.size
    np.testing.assert_array_equal(F[step, asperity], force)

    # Each contact relative to the footprint centre: inside the footprint
    # and its selection margin.
    xi = r["positions"][s["asperity"], 0] - s["position"][s["step"]]
    eta = r["positions"][s["asperity"], 1] - s["lateral"]
    tread, margin = rolling["tread"], quantity(rolling["margin"])
    assert np.all(np.abs(xi) <= quantity(tread["length"]) / 2 + margin + 1e-12)
    assert np.all(np.abs(eta) <= quantity(tread["width"]) / 2 + margin + 1e-12)
    # A road fixed in space moves back through the footprint: the same
    # asperity is met at a later step nearer the footprint's rear.
    first = asperity == asperity[0]
    assert np.all(np.diff(xi[first]) < 0)


def test_rolling_road_npz(rolling_out: Path) -> None:
    road = np.load(rolling_out / "road.npz")
    n = road["ids"].size
    np.testing.assert_array_equal(road["ids"], np.arange(n))
    assert road["positions"].shape == (n, 2)
    assert road["heights"].shape == (n,)
    assert np.all(np.isfinite(road["positions"])) and np.all(np.isfinite(road["heights"]))


def test_pressure_maps_integrate_to_the_load(texture_run: tuple[Path, dict]) -> None:
    out, spec = texture_run
    name = spec["name"]
    loads = [quantity(w) for w in spec["static"]["loads"]]
    summary = read_csv(out / f"{name}_summary.csv")
    np.testing.assert_allclose(summary["load_n"], loads)
    for load in loads:
        field = np.load(out / f"{name}_pressure_{load:g}N.npz")
        p = field["pressure"]
        x, y = field["x"], field["y"]
        dx, dy = field["spacing"]
        assert p.shape == (y.size, x.size)
        assert np.all(p >= 0.0) and p.max() > 0.0
        np.testing.assert_allclose(np.diff(x), dx, rtol=1e-9)
        np.testing.assert_allclose(np.diff(y), dy, rtol=1e-9)
        np.testing.assert_allclose(field["origin"], [x[0], y[0]], rtol=1e-12)
        assert p.sum() * dx * dy == pytest.approx(load, rel=1e-6)


def test_height_map_has_the_scenario_grid(texture_run: tuple[Path, dict]) -> None:
    out, spec = texture_run
    synth = spec["texture"]["synth"]
    height_map = np.load(out / f"{spec['name']}_height_map.npz")
    heights = height_map["heights"]
    assert heights.dtype == np.float64
    assert heights.shape == (synth["ny"], synth["nx"])
    spacing = quantity(synth["spacing"])
    np.testing.assert_allclose(height_map["spacing"], [spacing, spacing], rtol=1e-12)
    assert np.isfinite(heights).any()
