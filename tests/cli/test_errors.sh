# Exit codes (0 ok, 2 usage, 1 failure) and one-line error messages of the tools.
source "$(dirname "$0")/lib.sh"

for tool in h5check synth-meshseq; do
  run $tool --help
  expect_rc 0
  expect_out "Options:"
  expect_out "--quiet"
  run $tool --version
  expect_rc 0
  expect_out "$tool \(deformflow\) [0-9]+\.[0-9]+"
  run $tool --no-such-option
  expect_rc 2
  expect_err "^$tool: error: "
done

run synth-meshseq --kind finger          # missing -o
expect_rc 2
expect_err "output"
run synth-meshseq --kind blob -o x.h5
expect_rc 2
run synth-meshseq --frames 0 -o x.h5
expect_rc 2
run synth-meshseq -q -v -o x.h5
expect_rc 2

run synth-meshseq -q --frames 3 -o f.h5
expect_rc 0
[ -f f.h5 ] || fail "no output"
[ -s err.txt ] && fail "--quiet printed: $(cat err.txt)"
run synth-meshseq --frames 3 -o loud.h5    # progress as plain lines when stderr is a file
expect_rc 0
expect_err "^synth-meshseq: generating frames: 3/3 \(100%\).*done$"
grep -q $'\r' err.txt && fail "carriage returns in redirected progress"
run synth-meshseq -q --frames 3 -o f.h5   # exists, no --force
expect_rc 1
expect_one_error_line synth-meshseq
expect_err "output exists; use --force to overwrite it \(f.h5\)"
run synth-meshseq -q --frames 3 -f -o f.h5
expect_rc 0
run synth-meshseq -q --frames 3 -o no/such/dir/f.h5
expect_rc 1
expect_err "directory does not exist"

run h5check f.h5
expect_rc 0
expect_out "f.h5: OK, acap"
expect_out "/frames/positions +float32 +\[3,1042,3\] shuffle zstd"
expect_out "history:"

run h5check missing.h5
expect_rc 1
expect_err "^h5check: error: no such file \(missing.h5\)$"
echo "not hdf5" > text.h5
run h5check text.h5 f.h5                  # one bad file, one good: keeps going, exit 1
expect_rc 1
expect_err "not an HDF5 file \(text.h5\)"
expect_out "f.h5: OK"
run h5check --kind skeleton f.h5
expect_rc 1
expect_err "is a 'acap' file, expected a 'skeleton' file \(f.h5\)"
run h5check --kind nonsense f.h5
expect_rc 1
expect_err "unknown file kind 'nonsense'"
# A deformflow file with a NaN planted by h5py-free means: copy and patch with h5repack? Not
# available; the schema unit tests cover value violations. Here: a foreign HDF5 file.
h5import /dev/null -c /dev/null -o foreign.h5 >/dev/null 2>&1 || true
if [ -f foreign.h5 ]; then
  run h5check foreign.h5
  expect_rc 1
fi
echo "ok"
