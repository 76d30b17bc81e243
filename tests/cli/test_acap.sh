# obj2acap -> acap2obj end to end: round-trip error, thread independence, verbose objectives,
# MD2 input, errors with exit codes and no partial output.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

synth-meshseq -q --kind finger --frames 24 --resolution 12 --twist 240 -o frames
run obj2acap -v frames -o f.h5
expect_rc 0
expect_err "axis agreement [0-9-]+ -> [0-9-]+, angle spread"
h5check -q --kind acap f.h5

# Round trip: acap2obj reports the error against the stored positions.
run acap2obj f.h5 -o back
expect_rc 0
[ "$(ls back | wc -l)" = 24 ] || fail "expected 24 meshes"
err=$(sed -n 's/.*round-trip error.*: max \([0-9.e+-]*\) x bbox.*/\1/p' err.txt)
[ -n "$err" ] || fail "no round-trip error reported: $(cat err.txt)"
# (floor: the float32 storage of the positions the error is measured against)
awk -v e="$err" 'BEGIN { exit !(e < 1e-6) }' || fail "round-trip error $err >= 1e-6 of the diagonal"
# -v: the factorisation's time in its parts
run acap2obj -v --frames 0 f.h5 -o back-v
expect_rc 0
expect_err "of which: assembly [0-9.]+ s, ordering and analysis [0-9.]+ s, numeric factorisation [0-9.]+ s \\([0-9.]+ GFLOP"
run acap2obj --solver edges f.h5 -o back-edges       # the papers' system: approximate
expect_rc 0
expect_err "edge system"
err=$(sed -n 's/.*round-trip error.*: max \([0-9.e+-]*\) x bbox.*/\1/p' err.txt)
awk -v e="$err" 'BEGIN { exit !(e > 1e-6 && e < 1e-2) }' || fail "edge-system round-trip error $err unexpected"

# Same bytes at 1 and 2 threads.
obj2acap -q --threads 1 frames -o t1.h5
obj2acap -q --threads 2 frames -o t2.h5
for ds in /features/raw /features/normalized /frames/positions /normalization/min; do
  run h5diff t1.h5 t2.h5 $ds
  expect_rc 0
done
acap2obj -q --threads 1 t1.h5 -o m1
acap2obj -q --threads 2 t1.h5 -o m2
diff -r m1 m2 >/dev/null || fail "acap2obj meshes differ between 1 and 2 threads"

# --reference, --normalize per-dim, --anchor.
run obj2acap --reference frames/0005.obj --normalize per-dim frames -o ref.h5
expect_rc 0
expect_err "reference frames/0005.obj"
run h5dump -a /normalization/mode ref.h5
expect_out '"per-dim"'
run h5dump -d /features/raw -s 5,0,0 -c 1,1,9 ref.h5   # frame 5 is the reference: r = 0, s = I
sed -n 's/.*(5,0,0): //p' out.txt | tr -d ' ' | awk -F, '{
  split("0,0,0,1,0,0,1,0,1", e, ","); for (k = 1; k <= 9; k++) if ($k - e[k] > 1e-12 || e[k] - $k > 1e-12) exit 1
}' || fail "reference frame features are not r = 0, s = I: $(grep '(5,0,0)' out.txt)"
run acap2obj --anchor 100 --anchor-positions reference --frames 0 f.h5 -o anchored
expect_rc 0
diff <(grep -m101 '^v ' anchored/0000.obj | tail -1) <(grep -m101 '^v ' frames/0000.obj | tail -1) >/dev/null ||
  fail "anchor vertex 100 not at its reference position"
run acap2obj --anchor 100000 f.h5 -o x
expect_rc 1
expect_err "anchor vertex 100000 does not exist"

# Selection, patterns, formats, HDF5 output.
run acap2obj f.h5 --frames 0-2,20- --name '{index:03d}.ply' -o sel
expect_rc 0
[ "$(ls sel | tr '\n' ' ')" = "000.ply 001.ply 002.ply 020.ply 021.ply 022.ply 023.ply " ] || fail "selection: $(ls sel)"
run acap2obj f.h5 --frames 5 -o one.h5
expect_rc 0
h5check -q one.h5

# MD2 keyframes (Debian assimp-testmodels): one labelled sequence per animation.
md2=/usr/share/assimp/models/MD2/faerie.md2
[ -f $md2 ] || fail "$md2 missing (scripts/install-deps.sh installs assimp-testmodels)"
run obj2acap $md2 -o faerie.h5
expect_rc 0
run h5check faerie.h5
expect_out "S = 16"
expect_out "C = 16"
run acap2obj faerie.h5 --sequence run -o run
expect_rc 0
[ "$(ls run | wc -l)" = 6 ] || fail "faerie 'run' should have 6 frames"

# Errors: one line, exit 1 (2 for usage), nothing left behind.
cp -r frames broken
sed -i '0,/^f \([0-9]*\) \([0-9]*\) \([0-9]*\)$/s//f \2 \1 \3/' broken/0010.obj
run obj2acap -q broken -o broken.h5
expect_rc 1
expect_one_error_line obj2acap
expect_err "connectivity differs.*first at triangle 1.*0010.obj"
[ -e broken.h5 ] && fail "partial output left"
expect_no_temporaries .
run obj2acap frames --normalize sideways -o x.h5
expect_rc 2
run obj2acap frames --labels a,b -o x.h5
expect_rc 2
expect_err "2 labels for 1 sequences"
run acap2obj frames/0000.obj -o x
expect_rc 1
expect_err "not an HDF5 file"
synth-meshseq -q --frames 3 -o positions-only.h5
run acap2obj positions-only.h5 -o x
expect_rc 1
expect_err "has no features"
run acap2obj f.h5 --frames 30-40 -o x
expect_rc 2
[ -e x ] && fail "output created on error"
echo "ok"
