#!/usr/bin/env bash
# Benchmarks (never run by the test suite). Usage: bench/run.sh [BUILD_DIR]
# Writes a Markdown table to BUILD_DIR/bench/results.md and prints it.
# So far: I/O foundations — synthetic frame generation + zstd HDF5 writing, and mesh reading
# of the real data when ../shared/data is present. Model/ACAP benchmarks join with their tools.
set -euo pipefail
build=${1:-build}
bin=$build/bin
out=$build/bench
mkdir -p "$out"
export HDF5_PLUGIN_PATH=$build/hdf5-plugins
results=$out/results.md

# seconds and peak RSS (MiB) of a command, via GNU time when installed
measure() {
  local log=$out/time.log
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "%e %M" -o "$log" "$@" >/dev/null
    awk '{printf "%.2f %.0f\n", $1, $2/1024}' "$log"
  else
    local t0 t1
    t0=$(date +%s.%N); "$@" >/dev/null; t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.2f n/a\n", b-a}'
  fi
}

{
  echo "| benchmark | threads | seconds | vertex-frames/s | peak MiB |"
  echo "|---|---|---|---|---|"
  # a 12,544-vertex grid (the size of the SPEC's performance targets)
  for threads in 1 2; do
    read -r s m < <(measure "$bin/synth-meshseq" -q --kind bumps --resolution 111 --frames 1000 \
                      --threads "$threads" -f -o "$out/bumps.h5")
    vf=$(awk -v s="$s" 'BEGIN{printf "%.0f", 112*112*1000/s}')
    echo "| synth-meshseq bumps 12,544 v x 1,000 frames -> zstd HDF5 | $threads | $s | $vf | $m |"
  done
  read -r s m < <(measure "$bin/h5check" -q "$out/bumps.h5")
  vf=$(awk -v s="$s" 'BEGIN{printf "%.0f", 112*112*1000/s}')
  echo "| h5check (reads + NaN-scans all positions) | 1 | $s | $vf | $m |"
} | tee "$results"
echo "results: $results"
