# Outputs do not depend on the thread count.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

for kind in finger bumps flag; do
  synth-meshseq -q --kind $kind --frames 150 --sequences 2 --seed 7 --threads 1 -o $kind-1.h5
  synth-meshseq -q --kind $kind --frames 150 --sequences 2 --seed 7 --threads 2 -o $kind-2.h5
  for ds in /frames/positions /template/vertices /template/faces; do
    run h5diff $kind-1.h5 $kind-2.h5 $ds
    expect_rc 0
  done
done
run h5diff bumps-1.h5 bumps-2.h5 /synthetic/weights
expect_rc 0
synth-meshseq -q --kind flag --frames 80 --threads 1 -o dir1
synth-meshseq -q --kind flag --frames 80 --threads 2 -o dir2
diff -r dir1 dir2 >/dev/null || fail "OBJ outputs differ between 1 and 2 threads"
[ "$(ls dir1 | wc -l)" = 80 ] || fail "expected 80 OBJ files"
echo "ok"
