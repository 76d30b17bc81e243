# The toolkit against a real Slurm (Debian's slurm-wlm 22.05): a single-node cluster on loopback
# (tests/slurm/cluster.sh), then
#   1. a small MSAE pipeline with LAUNCH=slurm writes byte-identical files to a local run;
#   2. a sweep runs as a job array and its collect job gathers the table; a failing task keeps
#      the collect job from running and is named with its error;
#   3. a training step signalled mid-run (scancel --signal=USR1: Slurm's time-limit warning; a
#      plain scancel: SIGTERM, as on preemption) checkpoints, is submitted again with --resume
#      by scripts/slurm-run and ends with weights identical to an uninterrupted run;
#   4. a failing pipeline step stops its dependents, and its error is visible.
# Slurm and munge are installed when missing (scripts/install-deps.sh --with-slurm); where that
# is impossible the test is skipped (exit 77) with the reason. The daemons are stopped at exit.
source "$(dirname "$0")/../cli/lib.sh"
: "${DF_PLUGIN_DIR:?}" "${DF_SOURCE:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR
unset MAKEFLAGS MFLAGS MAKELEVEL  # run from `make test`: our make calls start afresh

skip() { echo "SKIPPED: $*" >&2; exit 77; }
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  [ "$(id -u)" = 0 ] || sudo -n true 2>/dev/null ||
    skip "Slurm is not installed, and installing it needs root or password-less sudo: run scripts/install-deps.sh --with-slurm"
  echo "installing slurm-wlm and munge (scripts/install-deps.sh --with-slurm)"
  bash "$DF_SOURCE/scripts/install-deps.sh" --with-slurm >install.log 2>&1 ||
    skip "Slurm is not installed and could not be installed: $(tail -n 1 install.log)"
fi

cluster=$DF_TMP/cluster
trap 'bash "$DF_SOURCE/tests/slurm/cluster.sh" stop "$cluster"' EXIT
eval "$(bash "$DF_SOURCE/tests/slurm/cluster.sh" start "$cluster")"
echo "ok (cluster up: $(sinfo -h -o '%P %D node(s), %c CPUs, state %t'))"
slurm_jobs() { squeue -h --states=all -o '%j %T' | grep -E "^$1 " || true; }

# --- 1. a pipeline: local, then LAUNCH=slurm in the same place; every output byte-identical
export SOURCE_DATE_EPOCH=1700000000  # the history attributes' time stamp
pipeline=(-s -C "$DF_SOURCE" -f Makefile.data OUT="$DF_TMP/run" BIN="$DF_BIN" -j2
  MS_SETS=bumps MS_LEVEL3_SETS= MS_BUMPS="--frames 40 --resolution 8"
  bumps_MSAE="--split sequence --iterations 40 --batch 16" bumps_TUNED=
  MS_TUNED_SETS= TRAIN_THREADS=1
  "$DF_TMP/run/msae/bumps/table2.md" "$DF_TMP/run/msae/bumps/table4.md")
make "${pipeline[@]}" >local.log 2>&1 || fail "local pipeline: $(tail -5 local.log)"
mv run run-local
make "${pipeline[@]}" LAUNCH=slurm SLURM_train=-c1 SLURM_generate=-c1 SLURM_eval=-c1 \
  >slurm.log 2>&1 || fail "pipeline with LAUNCH=slurm: $(tail -5 slurm.log)"
compared=0
while IFS= read -r f; do
  [ -f "run/$f" ] || fail "LAUNCH=slurm did not write $f"
  cmp -s "run-local/$f" "run/$f" || fail "$f differs between the local and the Slurm run"
  compared=$((compared + 1))
done < <(cd run-local && find . -type f ! -name '*.log' | sort)
[ "$(cd run && find . -type f ! -name '*.log' | wc -l)" = "$compared" ] ||
  fail "the Slurm run wrote other files than the local run"
jobs=$(slurm_jobs 'df-bumps-[^ ]*' | grep -c COMPLETED)
# 8 trainings (5 MSAE models, PCA, SPLOCS on positions and on ACAP features), 6 reconstructions
# (one with codes fitted through the decoders), 18 evaluations (9 reconstructions, each aligned by
# a translation and rigidly)
[ "$jobs" = 32 ] || fail "expected the 32 expensive steps as Slurm jobs, saw $jobs: $(slurm_jobs 'df-[^ ]*')"
grep -q "df-bumps-msae.h5 COMPLETED" <<<"$(slurm_jobs 'df-bumps-msae.h5')" ||
  fail "the training step did not run as a Slurm job"
echo "ok (pipeline: $compared files byte-identical to the local run; $jobs steps ran as Slurm jobs)"

# --- 2. a sweep as a job array + collect job; then one whose second task fails
sweep_command='train-msae -q $OPTIONS --batch 8 --iterations 30 run-local/msae/bumps/data.h5 -o $OUT/m.h5 &&
  recon-msae -q $OUT/m.h5 run-local/msae/bumps/data.h5 -o $OUT/r.h5 &&
  eval-metrics -q $OUT/r.h5 run-local/msae/bumps/data.h5 --json $OUT/metrics.json'
printf '# K_z of the two levels\nkz2 --kz 2,2\n\nkz3 --kz 3,2 --seed 5\n' >kz.grid
DF_BIN=$DF_BIN "$DF_SOURCE/scripts/sweep" -o sweep --slurm --wait --sbatch "-c1" kz.grid \
  "$sweep_command" >sweep.out 2>&1 || fail "sweep: $(cat sweep.out)"
[ "$(cut -f1 sweep/table.tsv | xargs)" = "name kz2 kz3" ] || fail "sweep table: $(cat sweep/table.tsv)"
head -1 sweep/table.tsv | grep -q "	erms	" || fail "no E_rms column: $(head -1 sweep/table.tsv)"
grep -q "COMPLETED" <<<"$(slurm_jobs sweep-collect)" || fail "the collect job did not run"
# the same grid here gives the same table
DF_BIN=$DF_BIN "$DF_SOURCE/scripts/sweep" -o sweep-local -j 2 kz.grid "$sweep_command" >/dev/null 2>&1
cmp -s sweep/table.tsv sweep-local/table.tsv || fail "the local sweep's table differs"
printf 'good --kz 2,2\nbroken --kz 2,2 --no-such-option\n' >broken.grid
run env DF_BIN="$DF_BIN" "$DF_SOURCE/scripts/sweep" -o broken --slurm --wait --sbatch "-c1" \
  broken.grid "$sweep_command"
expect_rc 1
expect_err "run broken failed \(exit 2\)"
expect_err "The following argument was not expected: --no-such-option"
expect_err "collect job [0-9]+ ended CANCELLED DependencyNeverSatisfied"
[ -f broken/table.tsv ] && fail "a table was collected although a task failed"
[ -f broken/good/metrics.json ] || fail "the good task did not run"
echo "ok (sweep: job array + collect job; a failed task named, its collect job never ran)"

# --- 3. stopped by Slurm mid-run (USR1 as before a time limit, TERM as on preemption): the
# step is submitted again with --resume and ends with an uninterrupted run's weights
train=(train-msae --kz 3,2 --batch 16 --print-every 7 --checkpoint-every 0 --seed 3 --threads 1
  --iterations 3000 run-local/msae/bumps/data.h5)
"${train[@]}" -q -o straight.h5
for how in "--signal=USR1" ""; do
  name=df-stop$how
  rm -f stopped.h5
  "$DF_SOURCE/scripts/slurm-run" -c1 --job-name="$name" -- "${train[@]}" -o stopped.h5 >stop.log 2>&1 &
  pid=$!
  for _ in $(seq 1 500); do grep -q "iteration 7/" stop.log && break; sleep 0.02; done
  job=$(squeue -h -n "$name" -o %i | head -1)
  [ -n "$job" ] || fail "no running job $name: $(cat stop.log)"
  scancel $how "$job"
  set +e; wait $pid; rc=$?; set -e
  [ "$rc" = 0 ] || fail "scancel $how: slurm-run ended with $rc: $(tail -5 stop.log)"
  grep -q "stopped by SIG$([ -n "$how" ] && echo USR1 || echo TERM) after iteration" stop.log ||
    fail "scancel $how: the trainer did not stop at a checkpoint: $(cat stop.log)"
  grep -q "submitting it again with --resume" stop.log || fail "not resubmitted: $(cat stop.log)"
  grep -q "resuming from stopped.h5.ckpt" stop.log || fail "did not resume: $(cat stop.log)"
  for obj in /params /optimizer/m /optimizer/v /rng/state /training/log; do
    run h5diff straight.h5 stopped.h5 $obj; expect_rc 0
  done
  [ "$(slurm_jobs "$name" | wc -l)" = 2 ] || fail "expected 2 jobs $name: $(slurm_jobs "$name")"
  echo "ok (scancel ${how:-(SIGTERM)}: $(grep -o 'after iteration [0-9]*' stop.log | head -1), resubmitted, identical weights)"
done

# --- 4. a failing step: its dependents do not run; the error is in Make's output
mkdir -p broken-run/msae/bumps
cp run-local/msae/bumps/frames.h5 broken-run/msae/bumps/
printf 'not an HDF5 file\n' >broken-run/msae/bumps/data.h5
run make -s -C "$DF_SOURCE" -f Makefile.data OUT="$DF_TMP/broken-run" BIN="$DF_BIN" LAUNCH=slurm \
  SLURM_train=-c1 SLURM_generate=-c1 SLURM_eval=-c1 MS_SETS=bumps MS_LEVEL3_SETS= \
  "$DF_TMP/broken-run/msae/bumps/recon.h5"
[ "$rc" != 0 ] || fail "make succeeded on a broken input"
expect_out "train-msae: error: not an HDF5 file .*broken-run/msae/bumps/data.h5"  # (the log's tee)
expect_out "srun: error: .*Exited with exit code 1"
expect_err "make(\[[0-9]+\])?: \*\*\* .*broken-run/msae/bumps/msae.h5\] Error 1"
[ -f broken-run/msae/bumps/msae.h5 ] && fail "the failed step left an output"
[ -f broken-run/msae/bumps/recon.h5 ] && fail "the dependent step ran"
[ "$(slurm_jobs 'df-bumps-[^ ]*' | grep -c FAILED)" = 1 ] ||
  fail "expected one failed job: $(slurm_jobs 'df-bumps-[^ ]*' | grep -v COMPLETED)"
echo "ok (a failed step: $(grep -o 'train-msae: error: [^(]*' out.txt | head -1); dependents not run)"

bash "$DF_SOURCE/tests/slurm/cluster.sh" stop "$cluster"
trap - EXIT
left=$(pgrep -f "$cluster" || true)
[ -z "$left" ] || fail "daemons left running: $(ps -o pid,args -p $left)"
echo "ok (daemons stopped)"
