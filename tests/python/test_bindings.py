"""The Python bindings (bindings/python): geometry, laws, the multipoint solve
and scenario runs, each against an independent reference or the Rust side.

Skipped when the `tyreroad` package is not installed (CI installs it with
maturin first: .ci/run)."""

import _thread
import math
import os
import signal
import threading
import time
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
PAPER = ROOT / "fixtures" / "paper_25_spheres.toml"
ROLLING = ROOT / "fixtures" / "rolling_small.toml"
RUBBER = tr.Material(6.54e6, 0.5)


# --- exceptions -------------------------------------------------------------


def test_every_error_is_a_tyreroad_error():
    for name in [
        "InputError", "CoreError", "GeometryError", "LawError", "SolveError",
        "TextureError", "BemError", "FilmError", "RollingError", "ScenarioError",
        "FidelityError",
    ]:
        assert issubclass(getattr(tr, name), tr.Error)
    assert issubclass(tr.Error, Exception)


# --- material ---------------------------------------------------------------


def test_material_reduced_modulus():
    m = tr.Material(2.0e6, 0.3)
    assert m.youngs_modulus == 2.0e6 and m.poisson_ratio == 0.3
    assert m.reduced_modulus == pytest.approx(2.0e6 / (1 - 0.3**2), rel=1e-15)


@pytest.mark.parametrize("e, nu", [(-1.0, 0.3), (float("nan"), 0.3), (1e6, 0.7)])
def test_bad_material_raises_core_error_with_the_rust_message(e, nu):
    with pytest.raises(tr.CoreError) as info:
        tr.Material(e, nu)
    assert str(info.value)  # the Rust message, not empty


# --- cap measures against closed forms ---------------------------------------

DEPTHS = np.array([0.0, 1e-5, 1e-4, 5e-4, 1e-3])


def test_sphere_cap_closed_form():
    r = 5e-3
    cap = tr.Asperity.sphere(r, RUBBER).cap(DEPTHS)
    d = DEPTHS
    np.testing.assert_allclose(cap["volume"], np.pi * d**2 * (r - d / 3), rtol=1e-12, atol=0)
    np.testing.assert_allclose(cap["base_area"], np.pi * (2 * r * d - d**2), rtol=1e-12, atol=0)
    np.testing.assert_allclose(
        cap["perimeter"], 2 * np.pi * np.sqrt(2 * r * d - d**2), rtol=1e-12, atol=0
    )


def test_cone_and_paraboloid_caps_closed_form():
    theta = 1.2
    t = math.tan(theta)
    cone = tr.Asperity.cone(theta, RUBBER).cap(DEPTHS)
    np.testing.assert_allclose(cone["base_area"], np.pi * (DEPTHS * t) ** 2, rtol=1e-12)
    np.testing.assert_allclose(cone["volume"], np.pi * t**2 * DEPTHS**3 / 3, rtol=1e-12)
    rx, ry = 4e-3, 9e-3
    par = tr.Asperity.ellipsoid(rx, ry, RUBBER).cap(DEPTHS)
    np.testing.assert_allclose(par["base_area"], 2 * np.pi * DEPTHS * math.sqrt(rx * ry), rtol=1e-12)
    np.testing.assert_allclose(par["volume"], np.pi * DEPTHS**2 * math.sqrt(rx * ry), rtol=1e-12)


def octahedron(a):
    v = np.array(
        [[a, 0, 0], [-a, 0, 0], [0, a, 0], [0, -a, 0], [0, 0, a], [0, 0, -a]], dtype=np.float64
    )
    faces = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]],
        dtype=np.int64,
    )
    return v, faces


def test_mesh_cap_is_the_octahedron_pyramid():
    # Below the apex at depth d the section is a square of half-diagonal d.
    v, f = octahedron(2e-3)
    cap = tr.Asperity.mesh(v, f, RUBBER).cap(np.array([1e-4, 5e-4, 1e-3]))
    d = np.array([1e-4, 5e-4, 1e-3])
    np.testing.assert_allclose(cap["base_area"], 2 * d**2, rtol=1e-9)
    np.testing.assert_allclose(cap["volume"], 2 * d**3 / 3, rtol=1e-9)
    np.testing.assert_allclose(cap["perimeter"], 4 * math.sqrt(2) * d, rtol=1e-9)


def test_bad_meshes_and_shapes_raise_named_errors():
    v, f = octahedron(2e-3)
    with pytest.raises(tr.GeometryError):
        tr.Asperity.mesh(v, f[:-1], RUBBER)  # open mesh
    with pytest.raises(tr.InputError, match="faces"):
        tr.Asperity.mesh(v, f[:, :2].copy(), RUBBER)
    with pytest.raises(tr.InputError, match="faces: index"):
        tr.Asperity.mesh(v, f + 10, RUBBER)
    with pytest.raises(tr.GeometryError):
        tr.Asperity.sphere(-1e-3, RUBBER)
    with pytest.raises(tr.LawError):
        tr.Asperity.sphere(1e-3, RUBBER, constant=-0.1)


# --- the potential law -------------------------------------------------------


def test_law_is_consistent_force_is_du_and_stiffness_is_dp():
    ball = tr.Asperity.sphere(5e-3, RUBBER)
    d = np.linspace(1e-5, 1e-3, 9)
    h = 1e-8
    du = (ball.potential(d + h) - ball.potential(d - h)) / (2 * h)
    dp = (ball.force(d + h) - ball.force(d - h)) / (2 * h)
    np.testing.assert_allclose(ball.force(d), du, rtol=1e-5)
    np.testing.assert_allclose(ball.stiffness(d), dp, rtol=1e-5)
    assert np.all(ball.force(np.array([-1e-4, 0.0])) == 0.0)


def test_depth_arrays_are_checked():
    ball = tr.Asperity.sphere(5e-3, RUBBER)
    with pytest.raises(tr.InputError, match="float64"):
        ball.force(np.array([1, 2, 3]))
    with pytest.raises(tr.InputError, match="contiguous"):
        ball.force(np.linspace(0, 1e-3, 10)[::2])
    with pytest.raises(tr.InputError, match="1-D"):
        ball.force(np.zeros((2, 2)))


# --- the multipoint solve ----------------------------------------------------


def paper_from_rust():
    return tr.run_scenario(PAPER)


def test_paper_25_balls_from_python_equal_the_rust_validation_forces():
    # The Rust validation (`cargo xtask validate`) solves the paper fixture
    # through the scenario layer; here the same balls are built from NumPy
    # arrays and solved through `tyreroad.solve`.
    rust = paper_from_rust()
    positions = np.column_stack([rust["x"], rust["y"]])
    ball = tr.Asperity.sphere(5e-3, RUBBER, constant=0.36)
    for k, load in enumerate(rust["loads"]):
        s = tr.solve(positions, np.zeros(25), ball, RUBBER, load=load)
        expected = rust["forces"][k]
        np.testing.assert_allclose(s.forces, expected, rtol=1e-12, atol=0)
        assert abs(s.total_force - load) <= 1e-10 * load
        assert s.approach == pytest.approx(rust["approach"][k], rel=1e-12)
        # Independent of the Rust run: the layout's mirror symmetry.
        by_pos = {(round(x, 6), round(y, 6)): p for x, y, p in zip(rust["x"], rust["y"], s.forces)}
        for (x, y), p in by_pos.items():
            assert by_pos[(-x, y)] == pytest.approx(p, rel=1e-9)
            assert by_pos[(y, x)] == pytest.approx(p, rel=1e-9)


def test_approach_control_inverts_load_control():
    rng = np.random.default_rng(3)
    positions = rng.uniform(-0.02, 0.02, (12, 2))
    heights = rng.uniform(0, 2e-4, 12)
    balls = [tr.Asperity.sphere(r, RUBBER) for r in rng.uniform(3e-3, 6e-3, 12)]
    by_load = tr.solve(positions, heights, balls, RUBBER, load=80.0)
    by_approach = tr.solve(positions, heights, balls, RUBBER, approach=by_load.approach)
    assert by_approach.total_force == pytest.approx(80.0, rel=1e-7)
    np.testing.assert_allclose(by_approach.forces, by_load.forces, rtol=1e-6, atol=1e-9)
    assert by_load.contact_count == int(np.sum(by_load.forces > 0))
    assert np.all(by_load.radii[by_load.forces > 0] > 0)


def test_pressure_map_integrates_to_the_forces():
    positions = np.array([[-0.01, 0.0], [0.01, 0.0]])
    s = tr.solve(positions, np.zeros(2), tr.Asperity.sphere(5e-3, RUBBER), RUBBER, load=100.0)
    dx = 5e-5
    n = 600
    p = s.pressure_map(n, n // 2, dx, dx, origin=(-0.015, -0.0075))
    assert p.shape == (n // 2, n)
    assert p.sum() * dx * dx == pytest.approx(100.0, rel=1e-2)


def test_solve_refuses_bad_input():
    ball = tr.Asperity.sphere(5e-3, RUBBER)
    pos = np.zeros((3, 2))
    pos[:, 0] = [0.0, 0.01, 0.02]
    with pytest.raises(tr.SolveError, match="not finite"):
        tr.solve(pos, np.array([0.0, np.nan, 0.0]), ball, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match=r"\(N, 2\)"):
        tr.solve(np.zeros((3, 3)), np.zeros(3), ball, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match="float64"):
        tr.solve(pos.astype(np.float32), np.zeros(3), ball, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match="contiguous"):
        tr.solve(np.asfortranarray(pos), np.zeros(3), ball, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match="heights"):
        tr.solve(pos, np.zeros(2), ball, RUBBER, load=1.0)
    with pytest.raises(tr.InputError, match="exactly one"):
        tr.solve(pos, np.zeros(3), ball, RUBBER, load=1.0, approach=1e-4)
    with pytest.raises(tr.InputError, match="asperities"):
        tr.solve(pos, np.zeros(3), [ball, ball], RUBBER, load=1.0)
    with pytest.raises(tr.SolveError):
        tr.solve(np.zeros((2, 2)), np.zeros(2), ball, RUBBER, load=1.0)  # coincident


# --- scenarios and rolling ---------------------------------------------------


def test_scenario_as_dict_equals_the_file():
    import tomllib

    as_dict = tomllib.loads(PAPER.read_text())
    from_dict = tr.run_scenario(as_dict)
    from_file = paper_from_rust()
    assert from_dict["kind"] == "static"
    np.testing.assert_array_equal(from_dict["forces"], from_file["forces"])
    assert from_file["ids"] == list(range(1, 26))
    assert from_file["forces"].shape == (4, 25)
    assert np.all(from_file["solve_seconds"] > 0)


def test_scenario_errors_name_the_key():
    with pytest.raises(tr.ScenarioError, match="poisson"):
        tr.run_scenario({"name": "x", "description": "y", "material": {"youngs_modulus": "1 MPa", "poisson": 0.5}})
    with pytest.raises(tr.ScenarioError):
        tr.run_scenario(ROOT / "no_such_file.toml")
    with pytest.raises(tr.InputError):
        tr.run_scenario({"name": object()})


def test_rolling_signals_spectra_and_progress():
    calls = []
    r = tr.run_scenario(ROLLING, progress=lambda done, total: calls.append((done, total)))
    assert r["kind"] == "rolling"
    n = len(r["time"])
    assert n == 40 and calls[-1] == (40, 40)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    # Load control: every step carries the imposed 30 N.
    np.testing.assert_allclose(r["total_force"], 30.0, rtol=1e-8)
    np.testing.assert_allclose(np.diff(r["time"]), 1e-3 / (50 / 3.6), rtol=1e-9)
    assert r["sensor_forces"].shape == (1, n)
    assert np.all(r["sensor_forces"] <= r["total_force"] * (1 + 1e-12))
    assert len(r["band_centre"]) == len(r["band_level_db"]) > 0


def test_rolling_stops_when_progress_says_so_or_raises():
    # The rolling layer's interruption, reported by the scenario layer.
    with pytest.raises(tr.ScenarioError, match="interrupted after 5 of 40 steps"):
        tr.run_scenario(ROLLING, progress=lambda done, total: done < 5)

    def boom(done, total):
        raise ValueError("from the callback")

    with pytest.raises(ValueError, match="from the callback"):
        tr.run_scenario(ROLLING, progress=boom)


def test_ctrl_c_interrupts_a_rolling_run_between_steps():
    seen = []

    def interrupt(done, total):
        seen.append(done)
        time.sleep(0.02)  # a step as slow as a real road's
        if done == 3:
            _thread.interrupt_main()  # what Ctrl-C does

    assert threading.current_thread() is threading.main_thread()
    # A process started in the background by a non-interactive shell (as a
    # CI job may be) inherits SIGINT ignored, and Python then installs no
    # handler: interrupt_main() would do nothing. Ctrl-C's handler, as an
    # interactive session has it, for the length of this test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            tr.run_scenario(ROLLING, progress=interrupt)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert max(seen) < 40
