#!/usr/bin/env bash
# Writes a long texture road as a .npy height map (with its .npy.spacing
# sidecar) and the rolling scenario on it (docs/performance.md, "Distributed
# rolling", texture roads): random ellipsoidal chippings 2-6 mm across and
# 0.5-2.5 mm high on a 1 mm grid, (L + 0.1) m x 0.15 m, from a seed; the
# scenario is fixtures/rolling_small.toml's tyre and load on that texture,
# path from 50 mm to L + 50 mm at 1 mm steps (1000 L + 1 steps). Ranks read
# the .npy by windows (docs/distributed.md, "Memory per rank"). Never
# committed: made again from the seed. Needs python3 with numpy.
#
#   crates/distributed/scripts/long_texture.sh 10 /tmp/texture_10m.toml
set -euo pipefail
length_m=${1:?usage: long_texture.sh LENGTH_M OUT.toml}
out=${2:?usage: long_texture.sh LENGTH_M OUT.toml}
dir=$(cd "$(dirname "$out")" && pwd)
base=$(basename "$out" .toml)
npy="$dir/$base.npy"
python3 - "$length_m" "$npy" <<'PY'
import sys
import numpy as np
length, path = float(sys.argv[1]), sys.argv[2]
dx = 1e-3
nx, ny = int(round((length + 0.1) / dx)) + 1, 150
rng = np.random.default_rng(2006)
h = 20e-6 * rng.random((ny, nx))
n = int(nx * ny * dx * dx / (np.pi * 2e-3 * 2e-3))
for cx, cy, ax, ay, top in zip(rng.random(n) * nx * dx, rng.random(n) * ny * dx,
                               1e-3 + 2e-3 * rng.random(n), 1e-3 + 2e-3 * rng.random(n),
                               0.5e-3 + 2e-3 * rng.random(n)):
    i0, i1 = max(int((cx - ax) / dx), 0), min(int((cx + ax) / dx) + 2, nx)
    j0, j1 = max(int((cy - ay) / dx), 0), min(int((cy + ay) / dx) + 2, ny)
    x = np.arange(i0, i1) * dx
    y = np.arange(j0, j1)[:, None] * dx
    q = ((x - cx) / ax) ** 2 + ((y - cy) / ay) ** 2
    cap = np.where(q < 1, top * np.sqrt(np.clip(1 - q, 0, None)), 0.0)
    h[j0:j1, i0:i1] = np.maximum(h[j0:j1, i0:i1], cap)
np.save(path, h)
open(path + ".spacing", "w").write(f"{dx:e}\n")
PY
end=$(awk -v l="$length_m" 'BEGIN { printf "%.1f", 1000 * l + 50 }')
cat > "$out" <<TOML
name = "long_texture_${length_m}m"
description = "A tyre on ${length_m} m of chippings read from $base.npy by windows"

[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5

[rolling]
start = "50 mm"
end = "${end} mm"
step = "1 mm"
speed = "50 km/h"
margin = "10 mm"
threads = 1
checkpoint = false

[rolling.tread]
kind = "tyre"
radius_x = "0.3 m"
radius_y = "0.5 m"
length = "50 mm"
width = "40 mm"

[rolling.control]
load = "30 N"

[[rolling.sensor]]
name = "centre"
x0 = "55 mm"
x1 = "65 mm"
y0 = "-10 mm"
y1 = "10 mm"

[texture]
file = "$base.npy"
min_prominence = "0.2 mm"
min_area = "4 mm2"
TOML
echo "wrote $out and $npy: $(python3 -c "import numpy as np; a = np.load('$npy', mmap_mode='r'); print(a.shape)") points (ny, nx)"
