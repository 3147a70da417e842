"""Calling overhead: the paper's 25 balls at 500 N solved from Python.

The Rust side of the comparison is the criterion bench
`multipoint/paper_25_spheres_500N` (benches/multipoint.rs): same layout,
material, law and default solver options. Run against a release build
(`maturin develop --release`):

    python bindings/python/benches/paper_25_timeit.py

Also times the same solve on the Rust side inside `run_scenario` (the
scenario layer's own `Instant` around each load's solve). Prints the median and minimum of REPEATS timings of NUMBER solves each, per
solve. Figures: docs/performance.md, "Calling from Python".
"""

import statistics
import timeit

import numpy as np

import tyreroad as tr

REPEATS, NUMBER = 15, 2000

rubber = tr.Material(6.54e6, 0.5)
ball = tr.Asperity.sphere(5e-3, rubber)
k = np.arange(25)
positions = np.column_stack([(k % 5 - 2) * 0.01, (k // 5 - 2) * 0.01])
heights = np.zeros(25)


def once():
    return tr.solve(positions, heights, ball, rubber, load=500.0)


assert abs(once().total_force - 500.0) < 1e-8
times = [t / NUMBER for t in timeit.repeat(once, repeat=REPEATS, number=NUMBER)]
# The Rust side measured in the same process and build: the scenario layer
# times each load's solve (and its local contacts) with `Instant`.
PAPER = __import__("pathlib").Path(__file__).resolve().parents[3] / "fixtures" / "paper_25_spheres.toml"
rust = []
for _ in range(300):
    r = tr.run_scenario(PAPER)
    rust.append(r["solve_seconds"][list(r["loads"]).index(500.0)])
print(f"rust solve timed inside run_scenario, 500 N: median {statistics.median(rust) * 1e6:.2f} us, "
      f"min {min(rust) * 1e6:.2f} us (300 runs)")
print(f"python tyreroad.solve, 25 balls, 500 N: median {statistics.median(times) * 1e6:.2f} us, "
      f"min {min(times) * 1e6:.2f} us ({REPEATS} x {NUMBER} solves)")
