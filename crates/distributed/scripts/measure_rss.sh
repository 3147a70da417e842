#!/usr/bin/env bash
# Peak RSS and wall time per rank of `xtask mpi-run` on long synthetic roads
# (docs/performance.md, "Distributed rolling"). Needs a release xtask with MPI:
#   cargo build --release -p xtask --features mpi
#   crates/distributed/scripts/measure_rss.sh "0.5 2 10" "1 2 3" /tmp/rss
# MPI_RUN_ARGS adds arguments to mpi-run (e.g. --gather: rank 0 gathers every
# record before writing, the way before they were written as they arrive).
# Prints one line per run and rank: length_m ranks rank peak_rss_kib wall_s.
# ROAD_SCRIPT=long_texture.sh measures a .npy texture road instead (read by
# windows) of the synthetic sphere road.
set -euo pipefail
lengths=${1:-"0.5 2 10"}
ranks_list=${2:-"1 2 3"}
work=${3:-/tmp/tyreroad-rss}
here=$(cd "$(dirname "$0")/../../.." && pwd)
xtask=${XTASK:-${CARGO_TARGET_DIR:-$here/target}/release/xtask}
extra=${MPI_RUN_ARGS:-}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 RAYON_NUM_THREADS=1
mkdir -p "$work"
echo "# $(uptime)"
for length in $lengths; do
  "$here/crates/distributed/scripts/${ROAD_SCRIPT:-long_road.sh}" "$length" "$work/road_${length}m.toml" >/dev/null
  for ranks in $ranks_list; do
    out="$work/out_${length}m_np${ranks}"
    rm -rf "$out" "$work"/time_${length}_${ranks}_*
    mpirun --oversubscribe -np "$ranks" bash -c \
      "/usr/bin/time -f '%M %e' -o '$work/time_${length}_${ranks}_'\$OMPI_COMM_WORLD_RANK \
       '$xtask' mpi-run '$work/road_${length}m.toml' --out '$out' $extra >/dev/null"
    for ((r = 0; r < ranks; r++)); do
      echo "$length $ranks $r $(cat "$work/time_${length}_${ranks}_$r")"
    done
  done
done
echo "# $(uptime)"
