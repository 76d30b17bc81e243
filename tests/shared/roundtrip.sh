#!/usr/bin/env bash
# obj2acap | acap2obj round trips on the real data (label shared-data). Prints the measured
# max/mean vertex error per dataset (x bounding-box diagonal, per-component translation
# removed). The default gradient solver must reproduce every frame to 2e-6 (SPEC: 1e-4; the
# floor is the float32 storage of /frames/positions, which the error is measured against —
# in double precision the solver is exact to ~1e-13, see the unit tests); the
# SPEC/paper edge solver (--solver edges) is approximate on these meshes and is held to its
# recorded bound (measured value plus a margin) as a regression guard. See the README.
set -euo pipefail
: "${DF_BIN:?}" "${DF_SHARED_DATA:?}" "${DF_TMP:?}"
rm -rf "$DF_TMP" && mkdir -p "$DF_TMP" && cd "$DF_TMP"
status=0
while read -r set bound; do
  "$DF_BIN/obj2acap" -q "$DF_SHARED_DATA/$set/$set" -o "$set.h5"
  for solver in gradients edges; do
    "$DF_BIN/acap2obj" --solver $solver "$set.h5" -o "$set-$solver.h5" 2> log.txt
    line=$(grep "round-trip error" log.txt | sed 's/.*removed)://')
    max=$(sed -n 's/.*round-trip error.*: max \([0-9.e+-]*\) x bbox.*/\1/p' log.txt)
    limit=$([ $solver = gradients ] && echo 2e-6 || echo "$bound")
    echo "$set ($solver):$line (bound $limit)"
    awk -v e="$max" -v b="$limit" 'BEGIN { exit !(e <= b) }' || { echo "FAIL: $set $solver max $max > $limit"; status=1; }
  done
done <<'LIST'
pcow 0.035
chickenCrossing 0.05
cactus 0.007
cat-poses 0.04
lion-poses 0.055
lowpoly_cat 0.28
LIST
exit $status
