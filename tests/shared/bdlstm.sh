#!/usr/bin/env bash
# BD-LSTM tools on the real meshes (label shared-data): a short training run on pcow and on
# chickenCrossing (41 connected parts), predictions and completions of the held-out part, their
# evaluation against the data and against the linear baselines. A smoke test of the whole chain
# on real input (the numbers of the paper's experiments come from pipelines/bdlstm.mk).
set -euo pipefail
: "${DF_BIN:?}" "${DF_SHARED_DATA:?}" "${DF_TMP:?}"
rm -rf "$DF_TMP" && mkdir -p "$DF_TMP" && cd "$DF_TMP"
export PATH="$DF_BIN:$PATH"
fail() { echo "FAIL: $*" >&2; exit 1; }
for set in pcow chickenCrossing; do
  obj2acap -q "$DF_SHARED_DATA/$set/$set" -o "$set.h5"
  train-bdlstm -q --iterations 6 --window 8 --batch 2 --print-every 3 "$set.h5" -o "$set-model.h5"
  h5check -q --kind bdlstm-model "$set-model.h5"
  gen-bdlstm -q "$set-model.h5" "$set.h5" --test-every 8 --test-context 3 --initial 3 --length 10 -o "$set-pred.h5"
  gen-bdlstm -q "$set-model.h5" "$set.h5" --test-every 8 --test-context 3 --initial 2 --method linear --length 10 -o "$set-lin.h5"
  gen-bdlstm -q "$set-model.h5" "$set.h5" --mode complete --test-every 16 --gap 5 --samples 2 --retries 2 -o "$set-comp.h5" 2>/dev/null
  for f in pred lin comp; do
    eval-metrics "$set-$f.h5" "$set.h5" --json "$set-$f.json" > "$set-$f.txt"
    grep -q '"frames_measured": [1-9]' "$set-$f.json" || fail "$set $f: no frames measured"
    grep -qiE 'nan|inf' "$set-$f.txt" && fail "$set $f: non-finite metrics: $(cat "$set-$f.txt")"
    echo "$set $f: $(grep 'position error' "$set-$f.txt")"
  done
done
echo ok
