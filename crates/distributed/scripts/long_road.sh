#!/usr/bin/env bash
# Writes the scenario of a long flat-density synthetic road (docs/performance.md,
# "Distributed rolling"): fixtures/rolling_small.toml with the road lengthened to
# L + 0.1 m and the path from 50 mm to L + 50 mm at 1 mm steps (1000 L + 1 steps).
# The road is made from its seed by every rank (only the window a rank rolls on is
# held), so no road file is written or committed.
#
#   crates/distributed/scripts/long_road.sh 10 /tmp/road_10m.toml
set -euo pipefail
length_m=${1:?usage: long_road.sh LENGTH_M OUT.toml}
out=${2:?usage: long_road.sh LENGTH_M OUT.toml}
here=$(cd "$(dirname "$0")/../../.." && pwd)
road=$(awk -v l="$length_m" 'BEGIN { printf "%.4f", l + 0.1 }')
end=$(awk -v l="$length_m" 'BEGIN { printf "%.1f", 1000 * l + 50 }')
sed -e "0,/^name = .*/s//name = \"long_road_${length_m}m\"/" \
    -e "s/^start = .*/start = \"50 mm\"/" \
    -e "s/^end = .*/end = \"${end} mm\"/" \
    -e "s/^length = \"0.12 m\"/length = \"${road} m\"/" \
    "$here/fixtures/rolling_small.toml" > "$out"
echo "wrote $out: road ${road} m, path 50 mm .. ${end} mm"
