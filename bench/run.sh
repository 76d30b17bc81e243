#!/usr/bin/env bash
# Benchmarks (never run by the test suite). Usage: bench/run.sh [BUILD_DIR] [render]
# (with "render": only the render-mesh section, into BUILD_DIR/bench/render.md)
# Writes Markdown tables to BUILD_DIR/bench/results.md and prints them. Rates are vertex-frames
# per second of the whole tool run (reading, computing, compressing, writing); peak memory is
# GNU time's maximum resident set size.
set -euo pipefail
build=${1:-build}
bin=$build/bin
out=$build/bench
shared=${DEFORMFLOW_SHARED_DATA:-$(dirname "$0")/../../shared/data}
mkdir -p "$out"
export HDF5_PLUGIN_PATH=$build/hdf5-plugins
results=$out/results.md

# "seconds peakMiB" of a command; its stderr goes to $out/last.log
measure() {
  local log=$out/time.log
  /usr/bin/time -f "%e %M" -o "$log" "$@" >/dev/null 2>"$out/last.log"
  awk '{printf "%.2f %.0f\n", $1, $2/1024}' "$log"
}
rate() { awk -v n="$1" -v s="$2" 'BEGIN{printf "%.2f M", n/s/1e6}'; }
# A network benchmark (bench_nn_blocks, bench_bdlstm, bench_msae print lines
# "| label | parameters | median ms | min ms |"): each line as
# "label<TAB>parameters<TAB>median<TAB>min<TAB>peak MiB" with GNU time's peak of the run.
net_bench() {
  /usr/bin/time -f "%M" -o "$out/time.log" "$@" >"$out/net.txt"
  awk -v m="$(awk '{printf "%.0f", $1/1024}' "$out/time.log")" -F'|' \
    '{gsub(/^ +| +$/, "", $2); printf "%s\t%s\t%s\t%s\t%s\n", $2, $3 + 0, $4 + 0, $5 + 0, m}' "$out/net.txt"
}
# The PyTorch peer's timing lines and peak memory at 1 and 2 threads: peer SCRIPT ARGS...
peer=$(dirname "$0")/../../shared/peers/torch
have_peer() { [ -f "$peer/$1" ] && /usr/bin/python3 -c "import torch" 2>/dev/null; }
peer_timings() {
  for threads in 1 2; do
    (cd "$peer" && /usr/bin/time -f "    peak %M KiB" /usr/bin/python3 "$@" --threads $threads 2>&1 |
      grep -E "threads=|peak") | sed 's/^/    /'
  done
}

# Inputs: a 12,602-vertex finger (bend + 400 deg twist), 1,000 frames, as acap positions.
[ -f "$out/finger12k.h5" ] || "$bin/synth-meshseq" -q --kind finger --resolution 56 --frames 1000 \
  --twist 400 -o "$out/finger12k.h5"
declare -A dirs
if [ -d "$shared/meshseq" ]; then
  for set in pcow chickenCrossing; do
    if [ ! -d "$out/data/$set" ]; then
      mkdir -p "$out/data" && tar --zstd -xf "$shared/meshseq/$set.tar.zst" -C "$out/data"
    fi
    dirs[$set]=$out/data/$set
  done
  # issue 42's obj2acap case, a 48-frame OBJ sequence: pdance's first 48 frames (7,061 v)
  if [ -f "$shared/meshseq/pdance.tar.zst" ]; then
    if [ ! -d "$out/data/pdance48" ]; then
      mkdir -p "$out/data/pdance-all" "$out/data/pdance48"
      tar --zstd -xf "$shared/meshseq/pdance.tar.zst" -C "$out/data/pdance-all"
      for i in $(seq 1 48); do
        ln -sf "$(find "$(realpath "$out/data/pdance-all")" -name "$i.obj")" "$out/data/pdance48/$(printf %03d "$i").obj"
      done
    fi
    dirs[pdance48]=$out/data/pdance48
  fi
fi

# Pictures: a 10,000-vertex finger (flat/smooth shading, 3x3 supersampling), per frame and as sheets.
bench_render() {
  [ -f "$out/finger10k.h5" ] || "$bin/synth-meshseq" -q --kind finger --resolution 50 --frames 30 --twist 200 \
    -o "$out/finger10k.h5"
  [ -f "$out/finger10k-acap.h5" ] || "$bin/obj2acap" -q "$out/finger10k.h5" -o "$out/finger10k-acap.h5"
  local v f
  v=$("$bin/h5check" "$out/finger10k.h5" | sed -n 's/^ *V = \([0-9]*\).*/\1/p')
  f=$("$bin/h5check" "$out/finger10k.h5" | sed -n 's/^ *F = \([0-9]*\).*/\1/p')
  echo "### Pictures (render-mesh), finger of $v vertices, $f triangles"
  echo
  echo "| what | panel pixels | threads | seconds | per frame s | peak MiB |"
  echo "|---|---|---|---|---|---|"
  for size in 320 512; do
    for threads in 1 2; do
      rm -rf "$out/render-frames"
      read -r s m < <(measure "$bin/render-mesh" --threads $threads --view side --size $size "$out/finger10k.h5" \
                        -o "$out/render-frames/{index:02d}.png")
      echo "| 30 frames, one PNG each (reading included) | $size² | $threads | $s | $(awk -v s=$s 'BEGIN{printf "%.3f", s/30}') | $m |"
    done
  done
  for threads in 1 2; do
    read -r s m < <(measure "$bin/render-mesh" --threads $threads --view side "$out/finger10k.h5" "$out/finger10k.h5" \
                      "$out/finger10k.h5" --frames 0,10,20 -f -o "$out/render-sheet.png")
    echo "| sheet 3 rows × 3 frames, stored positions | 320² | $threads | $s | $(awk -v s=$s 'BEGIN{printf "%.3f", s/9}') | $m |"
  done
  for threads in 1 2; do
    read -r s m < <(measure "$bin/render-mesh" --threads $threads --view side "$out/finger10k-acap.h5" \
                      --error-vs "$out/finger10k.h5" --show-truth --frames 0,10,20 -f -o "$out/render-err.png")
    echo "| sheet 2 rows × 3 frames (truth row + an acap file of the same frames), coloured by error | 320² | $threads | $s | $(awk -v s=$s 'BEGIN{printf "%.3f", s/6}') | $m |"
  done
}
if [ "${2:-}" = render ]; then
  bench_render | tee "$out/render.md"
  exit 0
fi

# The machine's limits (bench_roofline) and each training step op by op against them, at 1 and
# 2 threads (the steps' shapes as in the sections below).
bench_profile() {
  local threads peak bw
  echo "### Machine limits and the training steps op by op"
  for threads in 1 2; do
    echo
    echo "#### $threads thread(s): bench_roofline"
    echo
    "$bin/bench_roofline" --threads $threads | tee "$out/roofline.txt" | grep '^|'
    read -r peak bw < <(sed -n 's/^roofline: .* peak \([0-9.]*\) GFLOP.s bandwidth \([0-9.]*\) GB.s/\1 \2/p' "$out/roofline.txt")
    echo
    local limits=(--threads $threads --peak-gflops "$peak" --bandwidth "$bw" --profile 3)
    if [ -n "${dirs[pcow]:-}" ]; then
      "$bin/bench_bdlstm" --iters 2 --warmup 1 --mesh "${dirs[pcow]}/1.obj" "${limits[@]}" | grep -v '^| BD-LSTM'
      "$bin/bench_msae" --iters 1 --warmup 1 --mesh "${dirs[pcow]}/1.obj" --mode distinct "${limits[@]}" | grep -v '^| MSAE'
    fi
    "$bin/bench_msae" --iters 1 --warmup 1 --grid 112 --mode full "${limits[@]}" | grep -v '^| MSAE'
    "$bin/bench_actgan" --case gan --iters 2 --warmup 1 "${limits[@]}" | grep -v '^| ActGAN'
  done
}
if [ "${2:-}" = profile ]; then
  bench_profile | tee "$out/profile.md"
  exit 0
fi

{
  echo "### ACAP conversion (obj2acap, acap2obj)"
  echo
  echo "| input | tool | threads | seconds | vertex-frames/s | peak MiB |"
  echo "|---|---|---|---|---|---|"
  bench_set() {  # key label input vertex-frames
    local name=$1 label=$2 input=$3 vf=$4
    for threads in 1 2; do
      read -r s m < <(measure "$bin/obj2acap" -q --no-consistency --threads $threads "$input" -f -o "$out/$name-nc.h5")
      echo "| $label | obj2acap --no-consistency (features only) | $threads | $s | $(rate $vf $s) | $m |"
      read -r s m < <(measure "$bin/obj2acap" -q --threads $threads "$input" -f -o "$out/$name.h5")
      echo "| $label | obj2acap (features + consistency) | $threads | $s | $(rate $vf $s) | $m |"
    done
    for threads in 1 2; do
      read -r s m < <(measure "$bin/acap2obj" --threads $threads "$out/$name.h5" -f -o "$out/$name-back.h5")
      local factor
      factor=$(sed -n 's/.*factored in \([0-9.]*\) s.*/\1/p' "$out/last.log")
      echo "| $label | acap2obj (exact gradient solver) → .h5, factorisation ${factor} s | $threads | $s | $(rate $vf $s) | $m |"
    done
    read -r s m < <(measure "$bin/acap2obj" --solver edges --threads 2 "$out/$name.h5" -f -o "$out/$name-back.h5")
    echo "| $label | acap2obj --solver edges (the papers' system) → .h5 | 2 | $s | $(rate $vf $s) | $m |"
    read -r s m < <(measure "$bin/acap2obj" --threads 2 "$out/$name.h5" -f -o "$out/$name-meshes")
    echo "| $label | acap2obj → OBJ files | 2 | $s | $(rate $vf $s) | $m |"
  }
  bench_set finger "finger 12,602 v × 1,000 (HDF5 in)" "$out/finger12k.h5" 12602000
  # A large template: 135,610 vertices, 8 frames (the factorisation dominates).
  [ -f "$out/finger136k.h5" ] || "$bin/synth-meshseq" -q --kind finger --resolution 184 --frames 8 -o "$out/finger136k.h5"
  "$bin/obj2acap" -q "$out/finger136k.h5" -f -o "$out/finger136k-acap.h5"
  for threads in 1 2; do
    read -r s m < <(measure "$bin/acap2obj" --threads $threads "$out/finger136k-acap.h5" -f -o "$out/finger136k-back.h5")
    factor=$(sed -n 's/.*factored in \([0-9.]*\) s.*/\1/p' "$out/last.log")
    echo "| finger 135,610 v × 8 (HDF5 in) | acap2obj (exact gradient solver) → .h5, factorisation ${factor} s | $threads | $s | $(rate 1084880 $s) | $m |"
  done
  if [ -n "${dirs[pdance48]:-}" ]; then  # short runs: the median of five
    for threads in 1 2; do
      times=()
      for _ in 1 2 3 4 5; do
        read -r s m < <(measure "$bin/obj2acap" -q --threads $threads "${dirs[pdance48]}" -f -o "$out/pdance48.h5")
        times+=("$s")
      done
      s=$(printf '%s\n' "${times[@]}" | sort -n | sed -n 3p)
      echo "| pdance 7,061 v × 48 (OBJ in; median of 5) | obj2acap (features + consistency) | $threads | $s | $(rate 338928 $s) | $m |"
    done
  fi
  if [ -n "${dirs[pcow]:-}" ]; then
    bench_set pcow "pcow 2,904 v × 204 (OBJ in)" "${dirs[pcow]}" 592416
    bench_set chicken "chickenCrossing 3,030 v × 400 (OBJ in)" "${dirs[chickenCrossing]}" 1212000
  fi
  echo
  echo "### Network building blocks (forward + backward + Adam, float32; shapes of ../shared/peers/torch/blocks.py)"
  echo
  echo "| block | threads | median ms | min ms | peak MiB |"
  echo "|---|---|---|---|---|"
  mesh_arg=()
  [ -n "${dirs[pcow]:-}" ] && mesh_arg=(--mesh "${dirs[pcow]}/1.obj")
  for threads in 1 2; do
    for block in 1 2 3 4; do
      net_bench "$bin/bench_nn_blocks" --threads $threads --only $block "${mesh_arg[@]}" |
        while IFS=$'\t' read -r label _ median min mib; do echo "| $label | $threads | $median | $min | $mib |"; done
    done
  done
  if have_peer blocks.py; then
    echo
    echo "PyTorch peer (same machine; \`install-deps.sh --with-bench\` installs python3-torch):"
    echo
    peer_timings blocks.py
  fi
  if [ -n "${dirs[pcow]:-}" ]; then
    echo
    echo "### BD-LSTM training iteration (paper 1; shapes of ../shared/peers/torch/bdlstm.py: seq [8,32,2904,9], 10.46 M parameters)"
    echo
    echo "| model | parameters | threads | median ms | min ms | peak MiB |"
    echo "|---|---|---|---|---|---|"
    for threads in 1 2; do
      net_bench "$bin/bench_bdlstm" --threads $threads --iters 10 --mesh "${dirs[pcow]}/1.obj" |
        while IFS=$'\t' read -r _ params median min mib; do
          echo "| BD-LSTM pcow | $params | $threads | $median | $min | $mib |"
        done
    done
    if have_peer bdlstm.py; then
      echo
      echo "PyTorch peer (bdlstm.py, nb=sparse, 10 timed iterations):"
      echo
      peer_timings bdlstm.py --mesh pcow --iters 10
    fi
  fi
  echo
  echo "### MSAE training iteration (paper 2; shapes of ../shared/peers/torch/msae.py: AE0 + 10 attention AEs, B = 256 drawn from 64 shapes)"
  echo
  echo "full: all 256 rows computed, as the peer does; distinct: the batch's distinct shapes weighted by their count (what train-msae does; same loss and gradient)"
  echo
  echo "| model | parameters | threads | median ms | min ms | peak MiB |"
  echo "|---|---|---|---|---|---|"
  msae_cases=()
  [ -n "${dirs[pcow]:-}" ] && msae_cases+=("--mesh ${dirs[pcow]}/1.obj --mode full" "--mesh ${dirs[pcow]}/1.obj --mode distinct")
  msae_cases+=("--grid 112 --mode full")
  for threads in 1 2; do
    for c in "${msae_cases[@]}"; do
      # shellcheck disable=SC2086
      net_bench "$bin/bench_msae" --threads $threads --iters 3 $c |
        while IFS=$'\t' read -r label params median min mib; do
          echo "| $label | $params | $threads | $median | $min | $mib |"
        done
    done
  done
  if have_peer msae.py; then
    echo
    echo "PyTorch peer (msae.py, nb=sparse):"
    echo
    peer_timings msae.py --mesh pcow grid --iters 5
  fi
  echo
  echo "### ActGAN training iterations (paper 3; shapes of ../shared/peers/torch/actgan.py: poses of 60, T = 50, 10 classes, B = 32, LSTMs of 256, FC 1024)"
  echo
  echo "| case | parameters | threads | median ms | min ms | peak MiB |"
  echo "|---|---|---|---|---|---|"
  for threads in 1 2; do
    for c in gan gan-all pretrain; do
      net_bench "$bin/bench_actgan" --case $c --threads $threads --iters 5 |
        while IFS=$'\t' read -r label params median min mib; do
          echo "| $label | $params | $threads | $median | $min | $mib |"
        done
    done
  done
  if have_peer actgan.py; then
    echo
    echo "PyTorch peer (actgan.py):"
    echo
    peer_timings actgan.py --iters 6 --warmup 2
  fi
  echo
  echo "### The LSTM products: packed once (nn/packed_product.h) against Eigen's, one thread"
  echo
  "$bin/bench_packed_product" --threads 1
  echo
  echo "### MMD_u^2 of eval-metrics (1000 x 1000 sequences of [50, 60], max over 14 bandwidths)"
  echo
  echo "| case | sequences | threads | median ms | min ms | peak MiB |"
  echo "|---|---|---|---|---|---|"
  for threads in 1 2; do
    for c in "" --per-frame; do
      # shellcheck disable=SC2086
      net_bench "$bin/bench_mmd" --threads $threads --iters 5 $c |
        while IFS=$'\t' read -r label params median min mib; do
          echo "| $label | $params | $threads | $median | $min | $mib |"
        done
    done
  done
  if have_peer mmd.py; then
    echo
    echo "PyTorch peer (mmd.py):"
    echo
    peer_timings mmd.py --iters 5 --warmup 1
  fi
  echo
  echo "### edit-shape: one edit (factorisation + solve), bumps 10,000 vertices, 60 components, 20 handles"
  echo
  echo "| benchmark | steps | threads | median ms | min ms | notes |"
  echo "|---|---|---|---|---|---|"
  for threads in 1 2; do
    "$bin/bench_edit" --threads $threads --iters 3 |
      awk -F'|' -v t=$threads '{ printf "|%s|%s| %s |%s|%s|%s|\n", $2, $3, t, $4, $5, $6 }'
  done
  echo
  echo "### Synthetic data"
  echo
  echo "| benchmark | threads | seconds | vertex-frames/s | peak MiB |"
  echo "|---|---|---|---|---|"
  for threads in 1 2; do
    read -r s m < <(measure "$bin/synth-meshseq" -q --kind bumps --resolution 111 --frames 1000 \
                      --threads "$threads" -f -o "$out/bumps.h5")
    echo "| synth-meshseq bumps 12,544 v × 1,000 → zstd HDF5 | $threads | $s | $(rate 12544000 $s) | $m |"
  done
  echo
  bench_render
  echo
  bench_profile
} | tee "$results"
echo "results: $results"
