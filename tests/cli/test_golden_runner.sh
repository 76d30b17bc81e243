# The golden-file runner itself (tests/golden/run.sh + golden_compare) fails when it should: a
# stored number changed beyond its tolerance (in an HDF5 dataset, a mesh file, stdout), a missing
# or extra output, another exit status; and passes within the tolerance.
source "$(dirname "$0")/lib.sh"
: "${DF_TEST_BIN:?}" "${DF_SOURCE:?}"
runner=$DF_SOURCE/tests/golden/run.sh
export DF_TEST_BIN
golden() { DF_TMP=$DF_TMP/work bash "$runner" "$@" >runner.txt 2>&1; }
expect_runner_fails() {  # expect_runner_fails CASE PATTERN: runner exits 1 and names PATTERN
  if golden "$1"; then fail "runner passed $1: $(cat runner.txt)"; fi
  grep -qE -- "$2" runner.txt || fail "runner output lacks /$2/: $(cat runner.txt)"
}

# A case of our own: a finger (HDF5) and two OBJ frames, and a line on stdout.
mkdir -p cases/t/c
cat >cases/t/c/cmd <<'EOF'
synth-meshseq -q --kind finger --frames 3 --resolution 3 --twist 200 -o f.h5
synth-meshseq -q --kind finger --frames 2 --resolution 3 -o objs
echo "mean error 0.125 over 2 frames"
EOF
golden --update cases/t/c || fail "update: $(cat runner.txt)"
golden cases/t/c || fail "a fresh case fails: $(cat runner.txt)"

# 1. an HDF5 dataset that differs: the expected file of another twist
cp -r cases/t/c cases/t/h5
synth-meshseq -q -f --kind finger --frames 3 --resolution 3 --twist 201 -o cases/t/h5/expected/f.h5
expect_runner_fails cases/t/h5 "f.h5/frames/positions\[1,[0-9]+,[0-9]\]: expected .* got .*tolerance"

# ... and a root attribute (the file's schema version)
cp -r cases/t/c cases/t/root
"$DF_TEST_BIN/h5_mutate" cases/t/c/expected/f.h5 cases/t/root/expected/f.h5 version
expect_runner_fails cases/t/root "f.h5/@schema_version: expected 99, got 1"

# 2. a mesh coordinate moved by 1e-3 (beyond the default tolerance), then within a stated one
cp -r cases/t/c cases/t/obj
awk '!done && /^v / { $2 = $2 + 0.001; done = 1 } { print }' cases/t/c/expected/objs/0001.obj >cases/t/obj/expected/objs/0001.obj
expect_runner_fails cases/t/obj "objs/0001.obj:[0-9]+"
echo "objs/*.obj 0.002 0" >cases/t/obj/tolerances
golden cases/t/obj || fail "a difference within the stated tolerance fails: $(cat runner.txt)"

# 3. a number on stdout, a missing output, an unexpected output, another exit status
cp -r cases/t/c cases/t/out
sed -i 's/0.125/0.126/' cases/t/out/expected/@stdout
expect_runner_fails cases/t/out "@stdout:1"
cp -r cases/t/c cases/t/missing
echo "touch extra.txt" >>cases/t/missing/cmd
rm cases/t/missing/expected/objs/0000.obj
expect_runner_fails cases/t/missing "objs/0000.obj: written, but not expected"
grep -q "extra.txt: written, but not expected" runner.txt || fail "extra output not named: $(cat runner.txt)"
cp -r cases/t/c cases/t/rc
echo 1 >cases/t/rc/expected/@rc
expect_runner_fails cases/t/rc "exit status 0, expected 1"
echo "ok"
