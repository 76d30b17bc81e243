# A training run killed with SIGKILL and resumed from its last checkpoint ends with weights,
# optimiser and RNG state identical to an uninterrupted run.
source "$(dirname "$0")/lib.sh"
: "${DF_TEST_BIN:?}" "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR
driver=$DF_TEST_BIN/nn_resume_driver

$driver -q --iterations 300 --every 40 --checkpoint straight-ck.h5 -o straight.h5
h5check -q --kind nn-checkpoint straight.h5

$driver -q --iterations 300 --every 40 --delay-ms 4 --checkpoint ck.h5 -o resumed.h5 &
pid=$!
for i in $(seq 1 1000); do [ -f ck.h5 ] && break; sleep 0.01; done
[ -f ck.h5 ] || fail "no checkpoint appeared"
sleep 0.3
kill -KILL $pid
set +e; wait $pid; set -e
[ -f resumed.h5 ] && fail "the run finished before it was killed"
killed_at=$(h5dump -a /iteration ck.h5 | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
echo "killed after checkpoint at iteration $killed_at"
[ "$killed_at" -lt 300 ] || fail "checkpoint already final"
$driver -q --iterations 300 --every 40 --checkpoint ck.h5 --resume -o resumed.h5
for obj in /params /optimizer/m /optimizer/v /rng/state; do
  run h5diff straight.h5 resumed.h5 $obj
  expect_rc 0
done
run h5dump -a /optimizer/step resumed.h5
expect_out "\(0\): 300"
echo "ok (resume)"

# A training step does not depend on the thread count.
$driver -q --threads 1 --iterations 60 --every 1000 --checkpoint t1-ck.h5 -o t1.h5
$driver -q --threads 2 --iterations 60 --every 1000 --checkpoint t2-ck.h5 -o t2.h5
run h5diff t1.h5 t2.h5 /params
expect_rc 0
echo "ok (threads)"

# The trainers stop on request: SIGUSR1 (Slurm's warning before a time limit) or SIGTERM
# (preemption) mid-interval -> a checkpoint after the iteration in progress, the output not
# written, exit status 75; the rerun with --resume ends bit-identical to an uninterrupted run,
# log included. SIGINT keeps its old meaning (die at once, temporaries removed, no checkpoint).
synth-meshseq -q --kind bumps --frames 40 --resolution 8 --seed 2 -o bumps.h5
obj2acap -q bumps.h5 -o data.h5
msae=(--kz 3,2 --batch 16 --print-every 7 --checkpoint-every 0 --seed 3 --iterations 3000)
train-msae -q "${msae[@]}" data.h5 -o straight-msae.h5
# stop_on SIGNAL NAME: starts a training, signals it once its first log row is out, waits.
stop_on() {
  rm -f "$2.h5" "$2.h5.ckpt" "$2.err"
  train-msae "${msae[@]}" data.h5 -o "$2.h5" 2>"$2.err" &
  local pid=$!
  for _ in $(seq 1 1000); do grep -q "iteration 7/" "$2.err" && break; sleep 0.01; done
  kill "-$1" $pid
  set +e; wait $pid; rc=$?; set -e
}
for sig in USR1 TERM; do
  stop_on $sig stopped
  [ "$rc" = 75 ] || fail "SIG$sig: expected exit 75, got $rc: $(tail -3 stopped.err)"
  grep -qE "^train-msae: warning: stopped by SIG$sig after iteration [0-9]+ of 3000; checkpoint stopped.h5.ckpt holds it" stopped.err ||
    fail "SIG$sig: no stop message: $(tail -3 stopped.err)"
  [ -f stopped.h5 ] && fail "SIG$sig: the output was written by a stopped run"
  h5check -q --kind msae-model stopped.h5.ckpt
  at=$(h5dump -a /iteration stopped.h5.ckpt | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
  train-msae -q "${msae[@]}" --resume data.h5 -o stopped.h5
  for obj in /params /optimizer/m /optimizer/v /rng/state /training/log; do
    run h5diff straight-msae.h5 stopped.h5 $obj; expect_rc 0
  done
  [ -f stopped.h5.ckpt ] && fail "the checkpoint outlived the finished run"
  echo "ok (SIG$sig at iteration $at: exit 75, resumed to identical weights and log)"
done
stop_on INT interrupted
[ "$rc" = 130 ] || fail "SIGINT: expected exit 130, got $rc"
[ -f interrupted.h5.ckpt ] && fail "SIGINT wrote a checkpoint"
expect_no_temporaries .
echo "ok (SIGINT dies at once)"
