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
