# What the tools promise about their outputs (README, "Reliability"), each tried as a user hits
# it: a read-only directory fails before any work; two writers of one output: the second fails at
# once naming the first; a SIGKILLed run's temporary is removed by the next run; no output is
# replaced without --force (reports included); a checkpoint is never silently dropped; the long
# jobs refuse an existing output before their work; a long run speaks within seconds.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT  # no background tool outlives a failed check

synth-meshseq -q --kind bumps --frames 60 --resolution 8 --seed 2 -o bumps.h5
obj2acap -q bumps.h5 -o data.h5
tiny=(--kz 3,2 --batch 16 --seed 3)

# run_readonly DIR CMD...: runs CMD (as `run` does) with DIR read-only: a read-only bind mount
# for root (chmod does not stop root), chmod a-w otherwise.
run_readonly() {
  local dir=$1
  shift
  if [ "$(id -u)" = 0 ]; then
    unshare -m true 2>/dev/null || fail "cannot make a read-only directory: root without unshare -m"
    run unshare -m sh -c 'mount --bind "$0" "$0" && mount -o remount,bind,ro "$0" "$0" && exec "$@"' "$dir" "$@"
  else
    chmod a-w "$dir"
    run "$@"
    chmod u+w "$dir"
  fi
}

# --- a read-only output directory fails before any work: a converter and a trainer
mkdir ro
run_readonly ro obj2acap bumps.h5 -o ro/a.h5
expect_rc 1; expect_one_error_line obj2acap; expect_err "cannot write in the output's directory: .*\(ro\)"
run_readonly ro train-msae "${tiny[@]}" --iterations 100000 data.h5 -o ro/m.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "cannot write in the output's directory"
[ -z "$(ls -A ro)" ] || fail "something was left in the read-only directory: $(ls -A ro)"
echo "ok (read-only directory: refused at once, one line)"

# --- two writers of one output: the second fails at once naming the first, the first finishes
synth-meshseq -q --frames 600 --resolution 40 -o big.h5
obj2acap big.h5 -o twice.h5 2>first.err &
first=$!
wait_for first.err "computing features"
run obj2acap big.h5 -o twice.h5
expect_rc 1; expect_one_error_line obj2acap
expect_err "another process \(PID $first\) is writing this output.*\(twice.h5\)"
wait $first || fail "the first writer failed: $(cat first.err)"
h5check -q --kind acap twice.h5
# the same of a trainer: its output, and its checkpoint under another output
train-msae "${tiny[@]}" --print-every 1000 --iterations 1000000 data.h5 -o t.h5 2>trainer.err &
first=$!
wait_for trainer.err "geodesic"
run train-msae "${tiny[@]}" --iterations 20 data.h5 -o t.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "another process \(PID $first\) is writing this output"
run train-msae "${tiny[@]}" --iterations 20 --checkpoint t.h5.ckpt data.h5 -o other.h5
expect_rc 1; expect_err "another process \(PID $first\) is writing this output; .*\(t.h5.ckpt\)"
[ -e other.h5 ] && fail "the refused trainer wrote its output"
kill -INT $first; set +e; wait $first; set -e
expect_no_temporaries .
[ -z "$(find . -maxdepth 1 -name '.*.lock')" ] || fail "lock files left: $(find . -maxdepth 1 -name '.*.lock')"
echo "ok (two writers: the second refused, the first's output whole)"

# --- a SIGKILLed writer's temporary is removed by the next run on the same output
synth-meshseq -q --frames 4000 --resolution 40 -o killed.h5 &
pid=$!
for _ in $(seq 1 500); do [ -n "$(find . -maxdepth 1 -name '.killed.h5.tmp-*')" ] && break; sleep 0.01; done
kill -KILL $pid; set +e; wait $pid 2>/dev/null; set -e
left=$(find . -maxdepth 1 -name ".killed.h5.tmp-$pid-*")
[ -n "$left" ] || fail "the killed writer left no temporary (nothing to test)"
synth-meshseq --frames 4 --resolution 8 -o killed.h5 2>rerun.err
[ -e "$left" ] && fail "the stale temporary $left is still there"
grep -q "removed $left, a temporary left by process $pid that no longer runs" rerun.err ||
  fail "the removal was not reported: $(cat rerun.err)"
echo "ok (stale temporary removed and reported)"

# --- reports are outputs: refused when they exist, replaced with --force
eval-metrics -q data.h5 data.h5 --json m.json --tsv m.tsv > /dev/null
for option in --json --tsv; do
  run eval-metrics -q data.h5 data.h5 $option "m.${option#--}"
  expect_rc 1; expect_err "output exists; use --force to overwrite it \(m.${option#--}\)"
done
echo '{}' > m.json
eval-metrics -q -f data.h5 data.h5 --json m.json > /dev/null
grep -q '"erms"' m.json || fail "--force did not replace the JSON"
echo "ok (eval-metrics --json/--tsv need --force to replace a file)"

# --- a checkpoint is never dropped silently: without --resume the rerun refuses, --force starts over
msae=(train-msae "${tiny[@]}" --print-every 7 --checkpoint-every 0 data.h5 -o stopped.h5)
"${msae[@]}" --iterations 3000 2>stop.err &
pid=$!
wait_for stop.err "iteration 7/"
kill -TERM $pid; set +e; wait $pid; rc=$?; set -e
expect_rc 75
at=$(h5dump -a /iteration stopped.h5.ckpt | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
run "${msae[@]}" --iterations 3000
expect_rc 1; expect_one_error_line train-msae
expect_err "a checkpoint of an earlier run is here \(at iteration $at\): --resume continues it, --force starts over and replaces it \(stopped.h5.ckpt\)"
[ -f stopped.h5.ckpt ] || fail "the refused rerun removed the checkpoint"
run "${msae[@]}" --iterations 20 --force
expect_rc 0; expect_err "warning: starting over \(--force without --resume\): the checkpoint stopped.h5.ckpt \(at iteration $at\) will be replaced"
echo "ok (checkpoint at iteration $at: refused without --resume, replaced with --force)"

# --- the long jobs refuse an existing output before reading anything: an unreadable model
# shows that nothing was read before the refusal
echo "not a model" > junk.h5
touch exists.h5
for cmd in "gen-bdlstm junk.h5 data.h5 --from 3 -o exists.h5" "extract-components junk.h5 data.h5 -o exists.h5" \
  "prune-components junk.h5 -o exists.h5" "recon-msae junk.h5 data.h5 -o exists.h5" \
  "fit-baseline junk.h5 data.h5 -o exists.h5" "gen-actgan junk.h5 -o exists.h5"; do
  run $cmd
  expect_rc 1; expect_err "output exists; use --force to overwrite it \(exists.h5\)"
done
echo "ok (gen-bdlstm, extract-components, prune-components, recon-msae, fit-baseline, gen-actgan refuse first)"

# --- every tool takes the common options, --threads included
for t in "$DF_BIN"/*; do
  [ -x "$t" ] && [ -f "$t" ] || continue
  "$t" --help > help.txt
  grep -q -- "--threads" help.txt || fail "$(basename "$t") has no --threads"
done
train-msae -q "${tiny[@]}" --iterations 10 data.h5 -o small.h5
extract-components -q small.h5 data.h5 -o comps.h5
prune-components -q --threads 1 comps.h5 -o kept.h5 > /dev/null
echo "ok (every tool takes --threads)"

# --- a long run speaks within seconds: a pace line before the first loss line, and a second
# 30 s after the first iteration, measured without it (it holds the set-up)
train-msae "${tiny[@]}" --print-every 1000000 --iterations 1000000 data.h5 -o slow.h5 2>slow.err &
pid=$!
wait_for slow.err "s/iteration so far; the next loss line at iteration 1000000"
wait_for slow.err "s/iteration since the first; the next loss line at iteration 1000000" 60
kill -INT $pid; set +e; wait $pid; set -e
grep -qE "iteration [0-9]+/1000000: loss" slow.err && fail "a loss line came before the pace line: $(cat slow.err)"
[ "$(grep -c 's/iteration' slow.err)" = 2 ] || fail "not two pace lines: $(cat slow.err)"
echo "ok (pace lines: $(grep -o 'iteration [0-9]*/1000000: [0-9.e-]* s/iteration [a-z ]*' slow.err | tr '\n' ';'))"

# --- a large input says so before its long check: a BD-LSTM checkpoint over 64 MB (the model
# file, without Adam's state, is a third of it)
synth-meshseq -q --frames 12 --resolution 23 -o big-finger.h5
obj2acap -q big-finger.h5 -o big-data.h5
train-bdlstm -q --iterations 1 --window 4 --batch 1 --checkpoint big-model.h5 big-data.h5 -o big-final.h5
run gen-bdlstm big-model.h5 big-data.h5 --from 2 --length 2 -o big-gen.h5
expect_rc 0
[ "$(head -1 err.txt)" = "gen-bdlstm: reading big-model.h5 ($(( ($(stat -c %s big-model.h5) + 500000) / 1000000 )) MB)" ] ||
  fail "no word before reading the large model: $(head -2 err.txt)"
rm -f big-*.h5
echo "ok (a large model is announced before it is read)"

# --- numbers and captions say what they are
# fit-baseline: PCA of 6 training shapes has 5 components, and the summary says 5
run fit-baseline --method pca small.h5 data.h5 -o pca.h5
expect_rc 0
expect_err "warning: PCA of 6 training shapes has 5 components, not 9"
expect_err "wrote 54 pca reconstructions \(5 components fitted on 6 training shapes\)"
# eval-metrics: a reconstruction's rows name its own frame and the data frame it stands for
recon-msae -q small.h5 data.h5 -o recon.h5
run eval-metrics -q recon.h5 data.h5 --steps 0,9
expect_out "^  pred frame truth frame +error +x diagonal$"
expect_out "^ +0 +1 +[0-9.e-]+ +[0-9.e-]+$"   # the first held-out shape is data frame 1
expect_out "^ +9 +11 +[0-9.e-]+ +[0-9.e-]+$"  # frame 10 trains
# render-mesh: columns captioned by the data frame a reconstruction stands for, components by name
run render-mesh -v --size 32 --frames 0,9 recon.h5 --error-vs data.h5 --show-truth -o r.png
expect_rc 0; expect_err "rows: ground truth \| recon; columns: data frame 1 \| data frame 11$"
extract-components -q small.h5 data.h5 -o comps-all.h5 --acap comps-acap.h5
run render-mesh -v --size 32 --frames 0,1 comps-acap.h5 -o c.png
expect_rc 0; expect_err "columns: component L0.0.0 \| component L0.0.1$"
# export-gltf: the frame rate and the animation's length, not a run time
run export-gltf --fps 24 --every 2 data.h5 -o d.glb
expect_err "wrote d.glb: 30 frames of [0-9]+ vertices as morph targets at 12 fps \(the animation plays 2.42 s\)"
echo "ok (PCA's component count, pred/truth frames, captions, glTF's length)"

# --- coarse then fine editing keeps the coarse step's handles where it put them
# vertex FILE V: frame 0's position of vertex V, "x y z"
vertex() { h5dump -d /frames/positions -s "0,$2,0" -c "1,1,3" -y -w 0 -m %.9g "$1" | sed -n '/DATA {/,/}/p' |
             tr -dc '0-9.e,\n-' | paste -sd' ' | tr -s ', ' ' ' | sed 's/^ //; s/ $//'; }
echo "20 0 0 0.3" > coarse.txt
edit-shape -q --include-pruned --levels 0 --handles coarse.txt --relative comps-all.h5 --fixed 0 -o coarse.h5
echo "60 0 0 0.1" > fine.txt
run edit-shape --include-pruned --levels 1 --handles fine.txt --relative --from coarse.h5 comps-all.h5 -o fine.h5
expect_rc 0; expect_err "holding the 2 handle\(s\) of coarse.h5's edit where they are \(--release-handles frees them\)"
for v in 0 20; do
  [ "$(vertex fine.h5 $v)" = "$(vertex coarse.h5 $v)" ] || fail "handle $v moved: $(vertex coarse.h5 $v) -> $(vertex fine.h5 $v)"
done
edit-shape -q --include-pruned --levels 1 --handles fine.txt --relative --from coarse.h5 --release-handles comps-all.h5 -o free.h5
[ "$(vertex free.h5 20)" != "$(vertex coarse.h5 20)" ] || fail "--release-handles held the coarse handle"
edit-shape --help > help.txt
grep -q "its handles: each stays where the coarse step put it" help.txt || fail "the help does not say it"
grep -q -- "--include-pruned to edit with them anyway" help.txt || fail "the help does not name --include-pruned"
echo "ok (coarse-then-fine: the coarse handles held; --release-handles frees them)"

# --- meshes that are fine are read: '+' numbers, a polygon that returns to a vertex
mkdir -p objs
printf 'v +0 +0 +0\nv +1.0 0 0\nv 0 +1e+0 0\nv +1 +1 +0.5\nf 1 2 3\nf +2 +4 +3\n' > objs/plus.obj
obj2acap -q objs/plus.obj -o plus.h5
[ "$(vertex plus.h5 3)" = "1 1 0.5" ] || fail "'+' coordinates misread: $(vertex plus.h5 3)"
# a polygon whose corners come back to vertices 2 and 3 (as assimp's concave_polygon.obj does):
# read alike as the reference and as a frame
printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 2 3 4 5 6\n' > objs/loop.obj
obj2acap -q objs/loop.obj objs/loop.obj -o loop.h5
h5check -q --kind acap loop.h5
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n' > objs/zero.obj
run obj2acap objs/zero.obj -o zero.h5
expect_rc 1; expect_one_error_line obj2acap; expect_err "face corner '0' names vertex 0: OBJ counts from 1 \(or back from -1\) \(objs/zero.obj:4\)"
touch objs/shape.stl
run obj2acap objs/shape.stl -o stl.h5
expect_rc 1; expect_err "unknown input format: expected a mesh file \(.obj, .off, .ply\), an MD2 model \(.md2\), an acap .h5 file"
echo "ok (meshes: '+' numbers, repeated polygon corners, face index 0, unknown format)"
