# BD-LSTM end to end on a tiny synthetic finger: train-bdlstm (resume, threads), gen-bdlstm
# (predict, samples, complete, linear baselines), eval-metrics, bad input: the properties of the
# results. Their stored expected numbers are the golden-file cases under tests/golden/.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

synth-meshseq -q --frames 60 --resolution 4 --periods 2 -o finger.h5
obj2acap -q finger.h5 -o data.h5
tiny=(--window 8 --batch 2 --latent 8 --hidden 8 --lstm-layers 1 --print-every 10 --seed 3)

# --- training: log, model file, thread independence
train-bdlstm -q "${tiny[@]}" --iterations 40 --threads 1 data.h5 -o m.h5
h5check -q --kind bdlstm-model m.h5
train-bdlstm -q "${tiny[@]}" --iterations 40 --threads 2 data.h5 -o m2.h5
for obj in /params /rng/state /training/log; do
  run h5diff m.h5 m2.h5 $obj; expect_rc 0
done
echo "ok (train, threads)"
log=$(h5_data m.h5 /training/log %.9g | tr -c '0-9.e+-' ' ')
read -r -a v <<<"$log"
# iteration total recon bidir kl l2, and the default early stopping's stopping column
[ "${#v[@]}" = 28 ] || fail "training log has ${#v[@]} numbers, expected 4 rows x 7"
echo "ok (train log: loss ${v[1]} -> ${v[19]})"

# --- the collapse warning: a run forced to collapse (the paper's form with the KL term 1000x)
# warns at its loss lines and at the end, in one line naming the remedies, and records it; the
# defaults (KL warm-up: no check before it ends) and a live latent do not warn.
attr() { h5dump -a "/training/log/$2" "$1" | awk '/\(0\):/ { print $2 }'; }
train-bdlstm "${tiny[@]}" --iterations 40 --paper-form --alpha-reg 100 data.h5 -o collapsed.h5 2>collapse.log
[ "$(grep -c 'warning: the latent has collapsed' collapse.log)" -ge 2 ] ||
  fail "a collapsed latent did not warn at a loss line and at the end: $(cat collapse.log)"
grep 'warning: the latent has collapsed' collapse.log | head -n 1 | grep -q -- "--kl-free-bits.*inspect-bdlstm" ||
  fail "the warning does not name the remedies and inspect-bdlstm: $(cat collapse.log)"
[ "$(attr collapsed.h5 latent_collapsed)" = 1 ] || fail "the model file does not record the collapse"
awk -v k="$(attr collapsed.h5 kl_per_frame)" 'BEGIN { exit !(k < 0.5) }' || fail "KL per frame not below the threshold"
# The same collapsing run with the threshold at 0: no warning, no collapse recorded.
train-bdlstm "${tiny[@]}" --iterations 40 --paper-form --alpha-reg 100 --collapse-threshold 0 data.h5 -o unchecked.h5 2>unchecked.log
! grep -q "collapsed" unchecked.log || fail "--collapse-threshold 0 still warned: $(cat unchecked.log)"
[ "$(attr unchecked.h5 latent_collapsed)" = 0 ] || fail "a model without the warning records a collapse"
train-bdlstm "${tiny[@]}" --iterations 40 data.h5 -o defaults.h5 2>defaults.log
! grep -q "collapsed" defaults.log || fail "the defaults warned during the KL warm-up: $(cat defaults.log)"
run train-bdlstm "${tiny[@]}" --iterations 4 --collapse-threshold -1 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-bdlstm
echo "ok (collapse warning)"

# --- the carried motion: none by default and in --paper-form, and an explicit --carry /
# --carry-fade wins over --paper-form; a fade outside [0, 1] is refused
cfg() { h5dump -a "/config/$2" "$1" | awk '/\(0\):/ { print $2 }'; }
[ "$(cfg defaults.h5 carry)" = 0 ] && [ "$(cfg defaults.h5 carry_fade)" = 1 ] ||
  fail "the defaults' carry: $(cfg defaults.h5 carry) fading $(cfg defaults.h5 carry_fade)"
[ "$(cfg collapsed.h5 carry)" = 0 ] || fail "--paper-form carries motion: $(cfg collapsed.h5 carry)"
train-bdlstm -q "${tiny[@]}" --iterations 2 --paper-form --carry 0.5 --carry-fade 0.9 data.h5 -o pf-carry.h5
[ "$(cfg pf-carry.h5 carry)" = 0.5 ] && [ "$(cfg pf-carry.h5 carry_fade)" = 0.9 ] ||
  fail "--paper-form overrode an explicit --carry: $(cfg pf-carry.h5 carry) fading $(cfg pf-carry.h5 carry_fade)"
run train-bdlstm "${tiny[@]}" --iterations 2 --carry-fade 1.5 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-bdlstm; expect_err "--carry-fade must be in \[0, 1\] \(got 1.5\)"
echo "ok (carry: defaults, paper form, explicit options)"

# --- the motion input: on by default, off in --paper-form and with --no-motion-input; its scale
# is measured from the training frames (1 / RMS of a frame's change, > 1 for frames that move
# little), a resumed run equals the straight one, and a prediction runs (the stepper reads the
# motion too)
[ "$(cfg defaults.h5 motion_input)" = 1 ] || fail "the defaults do not read the motion"
train-bdlstm -q "${tiny[@]}" --iterations 2 --paper-form data.h5 -o pf.h5
[ "$(cfg pf.h5 motion_input)" = 0 ] || fail "--paper-form reads the motion"
train-bdlstm -q "${tiny[@]}" --iterations 2 --no-motion-input data.h5 -o no-motion.h5
[ "$(cfg no-motion.h5 motion_input)" = 0 ] || fail "--no-motion-input reads the motion"
train-bdlstm -q "${tiny[@]}" --iterations 20 --motion-input data.h5 -o motion.h5
[ "$(cfg motion.h5 motion_input)" = 1 ] || fail "--motion-input not recorded"
awk -v s="$(cfg motion.h5 motion_scale)" 'BEGIN { exit !(s > 1 && s < 1e6) }' ||
  fail "motion scale $(cfg motion.h5 motion_scale)"
train-bdlstm -q "${tiny[@]}" --iterations 10 --motion-input --checkpoint motion10.h5 data.h5 -o m10.h5
train-bdlstm -q "${tiny[@]}" --iterations 20 --motion-input --checkpoint motion10.h5 --resume data.h5 -o motion-resumed.h5
for obj in /params /rng/state /training/log; do
  run h5diff motion.h5 motion-resumed.h5 $obj; expect_rc 0
done
gen-bdlstm -q motion.h5 data.h5 --test-every 4 --initial 3 --length 4 -o motion-pred.h5
h5check -q --kind acap motion-pred.h5
echo "ok (motion input: on by default, off in the paper's form and with --no-motion-input, measured scale, resume, prediction)"

# --- windows at other speeds: 0, 0.5, 1 and 1.5 by default, the data's own pace (1, no draw) in
# --paper-form; a list is recorded, changes the training, and resumes bit-exactly; a negative speed
# and a speed whose window does not fit the training frames are refused, naming the option
h5dump -a /config/speeds defaults.h5 | grep -q "(0): 0, 0.5, 1, 1.5" || fail "the defaults' speeds: $(h5dump -a /config/speeds defaults.h5)"
[ "$(cfg pf.h5 speeds)" = 1 ] || fail "--paper-form plays windows at $(cfg pf.h5 speeds)"
train-bdlstm -q "${tiny[@]}" --iterations 20 --speeds 1 data.h5 -o speed1.h5
run h5diff motion.h5 speed1.h5 /params; expect_rc 1
train-bdlstm -q "${tiny[@]}" --iterations 20 --speeds 0,0.5,1,2 data.h5 -o speeds.h5
h5check -q --kind bdlstm-model speeds.h5
h5dump -a /config/speeds speeds.h5 | grep -q "0, 0.5, 1, 2" || fail "--speeds not recorded"
run h5diff motion.h5 speeds.h5 /params; expect_rc 1
train-bdlstm -q "${tiny[@]}" --iterations 10 --speeds 0,0.5,1,2 --checkpoint speeds10.h5 data.h5 -o s10.h5
train-bdlstm -q "${tiny[@]}" --iterations 20 --speeds 0,0.5,1,2 --checkpoint speeds10.h5 --resume data.h5 -o speeds-resumed.h5
run h5diff speeds.h5 speeds-resumed.h5 /params; expect_rc 0
run train-bdlstm "${tiny[@]}" --iterations 2 --speeds 1,-1 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-bdlstm; expect_err "--speeds must be in \[0, 8\] \(got 1,-1\)"
run train-bdlstm "${tiny[@]}" --iterations 2 --speeds 1,8 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "fastest of --speeds.*--speeds or --test-fraction"
# the remedies named are the options in use: a validation part adds its fraction (and the
# default's stopping part, dropped when it does not fit, is not named)
grep -q "stopping-fraction" err.txt && fail "the window error names --stopping-fraction, which is 0 here"
run train-bdlstm "${tiny[@]}" --iterations 2 --speeds 1,8 --validation-fraction 0.1 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "--speeds, --test-fraction or --validation-fraction"
# Sequences too short for a window at the default's fastest speed, long enough at the data's own
# pace, train at the default's speeds that fit, said in a warning (the paper's form trains them
# too); speeds asked for are never dropped, and a window too long at the data's pace is an error.
short=(--batch 2 --latent 8 --hidden 8 --lstm-layers 1 --seed 3 --iterations 2)
train-bdlstm -q "${short[@]}" --window 40 data.h5 -o slow.h5 2>slow.log
grep -q "warning: the sequences are too short for windows of 40 frames played at speed 1.5 (the default's fastest): training at speeds 0,0.5,1 " slow.log ||
  fail "no warning when the default's fastest speed leaves no window: $(cat slow.log)"
h5dump -a /config/speeds slow.h5 | grep -qE "\(0\): 0, 0.5, 1$" || fail "the speeds that fit: $(h5dump -a /config/speeds slow.h5)"
train-bdlstm -q --paper-form "${short[@]}" --window 40 data.h5 -o slow-paper.h5 2>slow-paper.log ||
  fail "the paper's form did not train 40-frame windows: $(cat slow-paper.log)"
! grep -q warning slow-paper.log || fail "the paper's form (speed 1 only) warned: $(cat slow-paper.log)"
run train-bdlstm -q "${short[@]}" --window 40 --speeds 0,0.5,1,1.5 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "fastest of --speeds"
run train-bdlstm -q "${short[@]}" --window 49 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "the longest has 48: use a smaller --window"
echo "ok (speeds: 0,0.5,1,1.5 by default, 1 in the paper's form, recorded, resumed, bad speeds refused, the default's that fit on short sequences)"

# --- early stopping (--stopping-fraction): a stopping part carved out of the training frames
# (/split/stopping), the log's stopping column, and a model file holding the weights of the loss
# line with the lowest stopping error (/training/best says which) — the weights a run stopped at
# that iteration ends with; a checkpoint keeps the last weights (and those beside them) and
# resumes bit-exactly. Off by default: no part, no column.
train-bdlstm -q "${tiny[@]}" --iterations 60 --lr 0.001 --stopping-fraction 0.1 --checkpoint es.ckpt data.h5 -o es.h5
h5check -q --kind bdlstm-model es.h5
h5check -q --kind bdlstm-model es.ckpt
h5dump -d /split/stopping es.h5 >/dev/null || fail "no stopping part recorded"
# A default (0.1), off in the paper's form; sequences too short for the default's part train
# without it, said in a warning (before the default's speeds are cut: the part goes first).
h5dump -d /split/stopping defaults.h5 >/dev/null || fail "the defaults carve no stopping part"
[ "$(cfg defaults.h5 stopping_fraction)" = 0.1 ] || fail "the defaults' stopping fraction: $(cfg defaults.h5 stopping_fraction)"
! h5dump -d /split/stopping pf.h5 >/dev/null 2>&1 || fail "--paper-form carves a stopping part"
train-bdlstm -q --batch 2 --latent 8 --hidden 8 --lstm-layers 1 --seed 3 --window 30 --iterations 2 data.h5 -o short.h5 2>short.log
grep -q "warning: the sequences are too short for early stopping's part.*last iteration's weights" short.log ||
  fail "no warning when the default's stopping part does not fit: $(cat short.log)"
[ "$(cfg short.h5 stopping_fraction)" = 0 ] || fail "the model of too-short sequences records a stopping part"
[ "$(cfg short.h5 stopping_every)" = 0 ] || fail "the model of too-short sequences records stopping checks"
# A part asked for keeps its place: the default's speeds yield to it (windows of 30 at speed 1.5
# no longer fit beside it), and where no window fits beside it even at the data's pace, an error.
train-bdlstm -q "${short[@]}" --window 30 --stopping-fraction 0.1 data.h5 -o asked.h5 2>asked.log
grep -q "training at speeds 0,0.5,1 " asked.log && ! grep -q "early stopping's part" asked.log ||
  fail "an asked-for stopping part did not keep its place: $(cat asked.log)"
h5dump -d /split/stopping asked.h5 >/dev/null || fail "the asked-for stopping part was dropped"
run train-bdlstm -q "${short[@]}" --window 44 --stopping-fraction 0.1 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "stopping-fraction"
best=$(h5dump -a /training/best/iteration es.h5 | awk '/\(0\):/ { print $2 }')
# The log's rows are iteration total recon bidir kl l2 stopping: the kept row has the lowest.
low=$(h5_data es.h5 /training/log %.9g | tr -c '0-9.e+-' ' ' |
  awk '{ for (i = 1; i <= NF; i++) v[n++] = $i } END { for (r = 0; r < n / 7; r++) if (r == 0 || v[7 * r + 6] < m) { m = v[7 * r + 6]; k = v[7 * r] } print k }')
[ -n "$best" ] && [ "$best" = "$low" ] || fail "kept iteration '$best', the log's lowest stopping error at '$low'"
[ "$best" -lt 60 ] || fail "this run's stopping error was lowest at its last line ($best): the test shows nothing"
run h5diff es.h5 es.ckpt /params; expect_rc 1  # the checkpoint: the last weights
train-bdlstm -q "${tiny[@]}" --iterations "$best" --lr 0.001 --stopping-fraction 0.1 --checkpoint es-best.ckpt data.h5 -o es-best.h5
run h5diff es.h5 es-best.ckpt /params; expect_rc 0  # the weights a run stopped there ends with
train-bdlstm -q "${tiny[@]}" --iterations 20 --lr 0.001 --stopping-fraction 0.1 --checkpoint es20.ckpt data.h5 -o es20.h5
train-bdlstm -q "${tiny[@]}" --iterations 60 --lr 0.001 --stopping-fraction 0.1 --checkpoint es20.ckpt --resume data.h5 -o es-resumed.h5
for obj in /params /training/log; do
  run h5diff es.h5 es-resumed.h5 $obj; expect_rc 0
done
[ "$(h5dump -a /training/best/iteration es-resumed.h5 | awk '/\(0\):/ { print $2 }')" = "$best" ] ||
  fail "the resumed run kept another iteration"
# --stopping-every N: the check runs between the loss lines too; the kept weights are again those
# of a run stopped at the kept iteration, here not a loss line's.
train-bdlstm -q "${tiny[@]}" --iterations 60 --lr 0.003 --stopping-fraction 0.1 --stopping-every 3 data.h5 -o ev3.h5
kept=$(h5dump -a /training/best/iteration ev3.h5 | awk '/\(0\):/ { print $2 }')
[ -n "$kept" ] && [ $((kept % 10)) != 0 ] || fail "--stopping-every 3 kept a loss line's weights ($kept): the test shows nothing"
train-bdlstm -q "${tiny[@]}" --iterations "$kept" --lr 0.003 --stopping-fraction 0.1 --stopping-every 3 --checkpoint ev3-kept.ckpt data.h5 -o ev3-kept.h5
run h5diff ev3.h5 ev3-kept.ckpt /params; expect_rc 0
[ "$(cfg ev3.h5 stopping_every)" = 3 ] || fail "--stopping-every not recorded"
# A run never ahead of zero motion on its stopping part (a step size too large) warns, once.
train-bdlstm "${tiny[@]}" --iterations 40 --lr 0.02 --stopping-fraction 0.1 data.h5 -o es-behind.h5 2>behind.log
[ "$(grep -c 'warning: early stopping: .*never ahead of zero motion.*method nearest' behind.log)" = 1 ] ||
  fail "no warning for a run never ahead of zero motion: $(cat behind.log)"
# --stopping-untrained checks the untrained network too: a run that only gets worse keeps it (with
# --decoder-init zero, zero motion itself: a stopping error of 1), the weights an untrained run has;
# without the flag the same run keeps a trained iteration.
kept_of() { h5dump -a /training/best/iteration "$1" | awk '/\(0\):/ { print $2 }'; }
train-bdlstm -q "${tiny[@]}" --iterations 40 --lr 0.02 --decoder-init zero --stopping-fraction 0.1 --stopping-untrained data.h5 -o es-untrained.h5
train-bdlstm -q "${tiny[@]}" --iterations 40 --lr 0.02 --decoder-init zero --stopping-fraction 0.1 data.h5 -o es-trained.h5
[ "$(kept_of es-untrained.h5)" = 0 ] && [ "$(kept_of es-trained.h5)" -gt 0 ] ||
  fail "--stopping-untrained kept iteration $(kept_of es-untrained.h5), without it $(kept_of es-trained.h5)"
train-bdlstm -q "${tiny[@]}" --iterations 0 --decoder-init zero --stopping-fraction 0.1 data.h5 -o es-0.h5
run h5diff es-untrained.h5 es-0.h5 /params; expect_rc 0
[ "$(cfg es-untrained.h5 stopping_untrained)" = 1 ] && [ "$(cfg es-trained.h5 stopping_untrained)" = 0 ] ||
  fail "--stopping-untrained not recorded: $(cfg es-untrained.h5 stopping_untrained)"
train-bdlstm "${tiny[@]}" --iterations 60 --lr 0.001 --stopping-fraction 0.1 -f data.h5 -o es.h5 2>ahead.log
grep -q "early stopping: the model file keeps the weights of iteration" ahead.log && ! grep -q "warning: early stopping" ahead.log ||
  fail "a run ahead of zero motion warned, or did not say which weights it kept: $(cat ahead.log)"
run train-bdlstm "${tiny[@]}" --iterations 2 --validation-fraction 0.5 --stopping-fraction 0.4 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-bdlstm; expect_err "stopping-fraction must be at least 0 and leave training frames"
echo "ok (early stopping: part, column, the kept weights are iteration $best's, resumed)"

# --- resume: the finished model file leaves out Adam's state (a third of a checkpoint's size) and
# is refused as a checkpoint, saying what to do; a checkpoint named with --checkpoint is kept with
# the final state, and resuming it to 40 iterations equals the straight run
train-bdlstm -q "${tiny[@]}" --iterations 20 --checkpoint ck.h5 data.h5 -o m20.h5
h5check -q --kind bdlstm-model m20.h5
h5check -q --kind bdlstm-model ck.h5
run h5ls m20.h5/optimizer; expect_rc 1
[ "$(h5dump -a /iteration ck.h5 | sed -n 's/.*(0): \([0-9]*\).*/\1/p')" = 20 ] || fail "the named checkpoint does not hold the final state"
for obj in /rng/state /training/log; do
  run h5diff m20.h5 ck.h5 $obj; expect_rc 0
done
# /params: the model file's are the default early stopping's kept weights, the checkpoint's the
# last ones — the same when the kept loss line is the last
kept=$(h5dump -a /training/best/iteration m20.h5 | awk '/\(0\):/ { print $2 }')
run h5diff m20.h5 ck.h5 /params
if [ "$kept" = 20 ]; then expect_rc 0; else expect_rc 1; fi
awk -v m="$(stat -c %s m20.h5)" -v c="$(stat -c %s ck.h5)" 'BEGIN { exit !(m < 0.5 * c) }' ||
  fail "model file $(stat -c %s m20.h5) bytes against the checkpoint's $(stat -c %s ck.h5)"
gen-bdlstm -q m20.h5 data.h5 --test-every 4 --initial 3 --length 4 -o m20-pred.h5
cp m20.h5 notck.h5
run train-bdlstm -q "${tiny[@]}" --iterations 40 --checkpoint notck.h5 --resume data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "finished model file.*checkpoint"
train-bdlstm -q "${tiny[@]}" --iterations 40 --checkpoint ck.h5 --resume data.h5 -o resumed.h5
for obj in /params /rng/state /training/log; do
  run h5diff m.h5 resumed.h5 $obj; expect_rc 0
done
[ -f ck.h5 ] || fail "a checkpoint named with --checkpoint was removed"
# A named checkpoint holds the run's final state: a 40-iteration run's (run30-first.h5) equals,
# optimizer included, that of a 30-iteration run's checkpoint resumed to 40 (the iteration it
# records is the state's: it once recorded 29 iterations for a state after 30). Checkpoints taken
# during a run and stops are tested in test_resume.sh.
train-bdlstm -q "${tiny[@]}" --iterations 40 --checkpoint-every 10 --checkpoint run30.h5 data.h5 -o full.h5
mv run30.h5 run30-first.h5
train-bdlstm -q "${tiny[@]}" --iterations 30 --checkpoint-every 10 --checkpoint run30.h5 data.h5 -o m30.h5
train-bdlstm "${tiny[@]}" --iterations 40 --checkpoint run30.h5 --resume data.h5 -o resumed-mid.h5 2>resume.log
grep -q "resuming from run30.h5 at iteration 30" resume.log || fail "expected to resume at iteration 30: $(head -n 1 resume.log)"
for obj in /params /rng/state /training/log; do
  run h5diff m.h5 resumed-mid.h5 $obj; expect_rc 0
done
for obj in /params /optimizer/m /optimizer/v /rng/state /training/log; do
  run h5diff run30-first.h5 run30.h5 $obj; expect_rc 0
done
train-bdlstm -q "${tiny[@]}" --iterations 20 --checkpoint-every 10 data.h5 -o own.h5
[ -f own.h5.ckpt ] && fail "the default checkpoint own.h5.ckpt was left behind"
run train-bdlstm -q --window 8 --batch 2 --latent 8 --hidden 9 --lstm-layers 1 --print-every 10 --seed 3 --iterations 40 --checkpoint ck.h5 --resume data.h5 -o bad.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "hidden"
echo "ok (resume)"

# --- a held-out part inside the sequence (--test-part middle): the test cases come from it
train-bdlstm -q "${tiny[@]}" --iterations 10 --test-part middle data.h5 -o mid.h5
ints() { h5_data "$2" "$1" | tr -c '0-9-' ' ' | xargs; }
[ "$(ints /split/test mid.h5)" = "24 36" ] || fail "middle held-out part is '$(ints /split/test mid.h5)', expected 24 36"
gen-bdlstm -q mid.h5 data.h5 --test-every 2 --initial 2 --length 4 -o midp.h5
src=$(ints /frames/source midp.h5)
[ -n "$src" ] || fail "no frames predicted from the middle part"
for f in $src; do [ "$f" -ge 24 ] && [ "$f" -lt 36 ] || fail "predicted frame of source $f is outside the held-out part 24..35"; done
echo "ok (held-out part in the middle: cases from frames $src)"

# --- a model trained on every 2nd frame (--stride 2) generates every 2nd frame
train-bdlstm -q "${tiny[@]}" --iterations 10 --stride 2 data.h5 -o s2.h5
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 3 --length 4 -o s2p.h5
[ "$(ints /frames/source s2p.h5)" = "46 48 50 52 54 56 58" ] || fail "stride-2 prediction sources: $(ints /frames/source s2p.h5)"
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 2 --length 5 --method linear -o s2l.h5
[ "$(ints /frames/source s2l.h5)" = "48 50 52 54 56 58 -1" ] || fail "stride-2 linear sources: $(ints /frames/source s2l.h5)"
# its first prediction continues frames 48 -> 50 (one feature checked): X50 + (X50 - X48)
feature() { h5dump -d /features/normalized -s "$2,3,4" -c "1,1,1" -y -w 0 -m %.9g "$1" | sed -n '/DATA {/,/}/p' | sed '1d;$d' | tr -d ' ,'; }
expect_close "stride-2 linear extrapolation" "$(feature s2l.h5 2)" \
  "$(awk -v a="$(feature data.h5 48)" -v b="$(feature data.h5 50)" 'BEGIN { printf "%.9g", 2 * b - a }')" 1e-6
# damped extrapolation: the step shrinks by --damping a frame (X50 + 0.5 d, X50 + 0.75 d);
# at 1 it is linear extrapolation, bit for bit
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 2 --length 5 --method damped --damping 0.5 -o s2d.h5
[ "$(ints /frames/source s2d.h5)" = "48 50 52 54 56 58 -1" ] || fail "damped sources: $(ints /frames/source s2d.h5)"
for k in 1 2; do
  expect_close "damped extrapolation, frame $k" "$(feature s2d.h5 $((k + 1)))" \
    "$(awk -v a="$(feature data.h5 48)" -v b="$(feature data.h5 50)" -v k=$k \
       'BEGIN { r = k == 1 ? 0.5 : 0.75; printf "%.9g", b + r * (b - a) }')" 1e-6
done
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 2 --length 5 --method damped --damping 1 -o s2d1.h5
h5diff -q -d 0 s2l.h5 s2d1.h5 /features/normalized || fail "damped extrapolation at 1 is not linear extrapolation"
gen-bdlstm -q s2.h5 data.h5 --mode complete --keyframes 20,30 -o s2c.h5
[ "$(ints /frames/source s2c.h5)" = "20 22 24 26 28 30" ] || fail "stride-2 completion sources: $(ints /frames/source s2c.h5)"
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 2 --length 2 --method static -o s2s.h5
[ "$(ints /frames/source s2s.h5)" = "48 50 52 54" ] || fail "static sources: $(ints /frames/source s2s.h5)"
# the given frames 48 -> 50 move; from the last given frame on, nothing does
eval-metrics -q s2s.h5 --tsv s2s.tsv >/dev/null
awk '/^#/ { next } NF == 2 && $1 == 0 && $2 == 0 { bad = 1 } NF == 2 && $1 > 0 && $2 != 0 { bad = 1 }
     NF == 2 { n++ } END { exit bad || n != 3 }' s2s.tsv || fail "static prediction is not the last given frame repeated: $(cat s2s.tsv)"
# motion matching: the training window (frames the model trained on, 2 apart) nearest to the
# given frames continues them; its cases are the static ones' frames
gen-bdlstm -q s2.h5 data.h5 --from 50 --initial 3 --length 2 --method nearest --neighbours 2 -o s2n.h5
[ "$(ints /frames/source s2n.h5)" = "46 48 50 52 54" ] || fail "nearest sources: $(ints /frames/source s2n.h5)"
eval-metrics -q s2n.h5 --tsv s2n.tsv >/dev/null
awk '/^#/ { next } NF == 2 && $1 > 0 && $2 == 0 { bad = 1 } END { exit bad }' s2n.tsv ||
  fail "motion matching predicted no motion on the moving finger: $(cat s2n.tsv)"
run gen-bdlstm -q s2.h5 data.h5 --mode complete --keyframes 20,30 --method nearest -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "nearest is a prediction reference"
run gen-bdlstm -q s2.h5 data.h5 --from 50 --method nearest --neighbours 0 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "neighbours"
run gen-bdlstm -q s2.h5 data.h5 --mode complete --keyframes 20,31 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "multiple of the stride"
run gen-bdlstm -q s2.h5 data.h5 --from 3 --initial 3 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "stride 2"
echo "ok (stride 2: generated frames 2 apart)"

# --- generation: deterministic for a seed, diverse across seeds
gen-bdlstm -q m.h5 data.h5 --from 50 --initial 3 --length 9 --samples 3 --seed 5 -o s5.h5
gen-bdlstm -q m.h5 data.h5 --from 50 --initial 3 --length 9 --samples 3 --seed 5 --threads 1 -o s5b.h5
run h5diff s5.h5 s5b.h5 /features/normalized; expect_rc 0
gen-bdlstm -q m.h5 data.h5 --from 50 --initial 3 --length 9 --samples 3 --seed 6 -o s6.h5
run h5diff -q s5.h5 s6.h5 /features/normalized; expect_rc 1
h5check -q --kind acap s5.h5
echo "ok (gen: deterministic, diverse)"

# --- predictions on the held-out part vs ground truth, and the linear baseline
gen-bdlstm -q m.h5 data.h5 --test-every 3 --initial 3 --length 6 -o pred.h5
gen-bdlstm -q m.h5 data.h5 --test-every 3 --initial 3 --length 6 --method linear -o lin.h5
eval-metrics pred.h5 data.h5 --steps 3,6 >pred.txt
eval-metrics lin.h5 data.h5 --steps 3,6 >lin.txt
step_error() { awk -v s="$1" '$1 == s && NF == 4 { print $3 }' "$2"; }
# linear extrapolation drifts: its error grows with the step; both tables have the steps
awk -v a="$(step_error 3 lin.txt)" -v b="$(step_error 6 lin.txt)" -v c="$(step_error 6 pred.txt)" \
  'BEGIN { exit !(a > 0 && b > a && c > 0) }' || fail "step errors: $(cat lin.txt pred.txt)"
grep -q "E_rms" lin.txt || fail "no E_rms in the table"
# The pace of a prediction (its motion per frame over the first 5 predicted frames against the
# data's): zero motion has none; linear extrapolation on this smooth finger is near the data's;
# the data's part is the same for every method of the same cases.
gen-bdlstm -q m.h5 data.h5 --test-every 3 --initial 3 --length 6 --method static -o still.h5
eval-metrics -q still.h5 data.h5 --json still.json > still.txt
eval-metrics -q lin.h5 data.h5 --json lin.json > /dev/null
pace() { collect-metrics --values --columns "pace.$2" "$1"; }
[ "$(pace still.json ratio)" = 0 ] && [ "$(pace still.json predicted_per_frame)" = 0 ] ||
  fail "zero motion has a pace: $(pace still.json ratio)"
[ "$(pace still.json true_per_frame)" = "$(pace lin.json true_per_frame)" ] && [ "$(pace lin.json steps)" = 5 ] ||
  fail "the data's pace differs between two methods of the same cases"
awk -v r="$(pace lin.json ratio)" 'BEGIN { exit !(r > 0.5 && r < 2) }' || fail "linear extrapolation's pace $(pace lin.json ratio)"
n=$(pace lin.json cases)  # one row per case, no more
[ -n "$(pace lin.json "per_case.$((n - 1)).case")" ] && ! pace lin.json "per_case.$n.case" 2>/dev/null ||
  fail "pace.per_case does not have the $n cases"
grep -qE "^  pace +0 per frame, the data [0-9.e-]+ \(x bbox diagonal\), over the first 5 predicted frames of [0-9]+ cases: ratio 0.000$" still.txt ||
  fail "the table's pace line: $(grep pace still.txt)"
eval-metrics data.h5 data.h5 --json same.json >/dev/null
awk '/"vertex_error"/ { getline; if ($2 + 0 == 0) ok1 = 1 } /"erms":/ { if ($2 + 0 == 0) ok2 = 1 }
     END { exit !(ok1 && ok2) }' same.json || fail "a file against itself has a non-zero error: $(head -c 400 same.json)"
# Feature change over a span: lin.h5's cases are 3 given frames, then a linear extrapolation of
# the last two, so from index 1 on X_t+2 - X_t = 2 (X_t+1 - X_t): the span-2 change at index 1 is
# twice the span-1 change (equal values would mean the span is ignored).
change1() { eval-metrics -q lin.h5 --change-span "$1" --tsv "span$1.tsv" >/dev/null
            awk '/^# feature_change/ { on = 1; next } on && $1 == 1 { print $2 }' "span$1.tsv"; }
c1=$(change1 1); c2=$(change1 2)
expect_close "span-2 feature change of a linear sequence" "$c2" "$(awk -v c="$c1" 'BEGIN { print 2 * c }')" 1e-4
run eval-metrics lin.h5 --change-span 0
expect_rc 2; expect_one_error_line eval-metrics; expect_err "change-span"
echo "ok (eval: linear step 3/6 $(step_error 3 lin.txt) $(step_error 6 lin.txt), bdlstm step 6 $(step_error 6 pred.txt))"

# --- completion: keyframes are kept exactly, the chains merge under a loose threshold
run gen-bdlstm m.h5 data.h5 --mode complete --keyframes 40,46,52 --samples 2 --merge-scale features --threshold 0.5 --blend 0 -o comp.h5
expect_rc 0; expect_err "every completion merged"
eval-metrics comp.h5 data.h5 --json comp.json >/dev/null
awk '/"step": 0,/ { getline; getline; if ($2 + 0 > 1e-6) bad = 1; seen = 1 } END { exit !(seen && !bad) }' comp.json ||
  fail "keyframes not reproduced: $(grep -A3 '"step": 0,' comp.json)"
gen-bdlstm -q m.h5 data.h5 --mode complete --keyframes 40,52 --method linear -o lcomp.h5
# each sample against the truth on its own: best of K <= mean of K <= worst of K
awk '/"samples_vs_truth"/ { on = 1 } on && /"(cases|mean_of_k|best_of_k|worst_of_k)":/ { gsub(/[",:]/, " "); v[$1] = $2 }
     END { exit !(v["cases"] == 1 && v["best_of_k"] > 0 && v["best_of_k"] <= v["mean_of_k"] && v["mean_of_k"] <= v["worst_of_k"]) }' comp.json ||
  fail "samples_vs_truth: $(grep -A8 samples_vs_truth comp.json)"
echo "ok (complete)"

# --- a long generation stays finite and moving
gen-bdlstm -q m.h5 data.h5 --from 0 --length 100 -o long.h5
eval-metrics long.h5 >long.txt
grep -q "feature change" long.txt || fail "no feature change for a single file"
echo "ok (long)"

# --- generation remedies (issue 18), the defaults: --restart never carries one chain's state (the
# window no longer matters; the paper's restarts every window differ); --latent sample draws z
# from q(z|x) (seeded; differs from the mean), --blend cross-fades the chains and keeps the
# keyframes exact, --merge weighted too
gen-bdlstm -q m.h5 data.h5 --from 10 --length 20 --window 30 --latent mean --restart window -o w30.h5
gen-bdlstm -q m.h5 data.h5 --from 10 --length 20 --window 30 --latent mean -o n30.h5
run h5diff w30.h5 n30.h5 /features/normalized; expect_rc 0
gen-bdlstm -q m.h5 data.h5 --from 10 --length 20 --window 5 --latent mean --restart never -o n5.h5
run h5diff n30.h5 n5.h5 /features/normalized; expect_rc 0
gen-bdlstm -q m.h5 data.h5 --from 10 --length 20 --window 5 --latent mean --restart window -o w5.h5
run h5diff -q w5.h5 n5.h5 /features/normalized; expect_rc 1
gen-bdlstm -q m.h5 data.h5 --from 10 --length 6 --latent sample --seed 2 -o ls1.h5
gen-bdlstm -q m.h5 data.h5 --from 10 --length 6 --latent sample --seed 2 --threads 1 -o ls2.h5
run h5diff ls1.h5 ls2.h5 /features/normalized; expect_rc 0
gen-bdlstm -q m.h5 data.h5 --from 10 --length 6 --latent mean -o lm.h5
run h5diff -q ls1.h5 lm.h5 /features/normalized; expect_rc 1
run gen-bdlstm m.h5 data.h5 --mode complete --keyframes 40,46,52 --samples 2 --threshold 2 --blend 3 --merge-scale motion -o compb.h5
expect_rc 0
eval-metrics compb.h5 data.h5 --json compb.json >/dev/null
awk '/"step": 0,/ { getline; getline; if ($2 + 0 > 1e-6) bad = 1; seen = 1 } END { exit !(seen && !bad) }' compb.json ||
  fail "blended completion: keyframes not reproduced: $(grep -A3 '"step": 0,' compb.json)"
run h5diff -q comp.h5 compb.h5 /features/normalized; expect_rc 1
gen-bdlstm -q m.h5 data.h5 --mode complete --keyframes 40,46,52 --samples 2 --merge weighted -o compw.h5
eval-metrics compw.h5 data.h5 --json compw.json >/dev/null
awk '/"step": 0,/ { getline; getline; if ($2 + 0 > 1e-6) bad = 1; seen = 1 } END { exit !(seen && !bad) }' compw.json ||
  fail "weighted completion: keyframes not reproduced: $(grep -A3 '"step": 0,' compw.json)"
run h5diff -q comp.h5 compw.h5 /features/normalized; expect_rc 1
run gen-bdlstm m.h5 data.h5 --mode complete --keyframes 40,52 --blend -1 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "blend"
echo "ok (remedies: restart never, latent sample, blend)"

# --- bad input: one line, the right exit code
synth-meshseq -q --frames 10 --resolution 5 -o other.h5
obj2acap -q other.h5 -o other-acap.h5
run gen-bdlstm m.h5 other-acap.h5 --from 5 -o x.h5
expect_rc 1; expect_one_error_line gen-bdlstm; expect_err "share the template"
run gen-bdlstm m.h5 data.h5 --from 1 --initial 3 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "only 2 frames"
# A mode's names are its choices: an unknown one is the option parser's error, naming them
run gen-bdlstm m.h5 data.h5 --mode sideways --from 5 -o x.h5
expect_rc 2; expect_err "^gen-bdlstm: error: --mode: sideways not in [{]predict,complete[}]"
run gen-bdlstm m.h5 data.h5 --from 5 --latent prior -o x.h5
expect_rc 2; expect_err "^gen-bdlstm: error: --latent: prior not in [{]mean,sample[}]"
run gen-bdlstm m.h5 data.h5 --keyframes 5,9 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "mode complete"
run gen-bdlstm m.h5 data.h5 --from 5 --method linear -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "initial 2"
run gen-bdlstm m.h5 data.h5 --from 5 --initial 2 --method damped --damping 1.5 -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "damping must lie in 0..1"
run gen-bdlstm m.h5 data.h5 --mode complete --keyframes 5,9 --method damped -o x.h5
expect_rc 2; expect_one_error_line gen-bdlstm; expect_err "damped is a prediction reference"
run train-bdlstm -q --window 100 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "smaller --window"
run train-bdlstm -q finger.h5 -o x.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "obj2acap"
run eval-metrics pred.h5 other-acap.h5
expect_rc 1; expect_one_error_line eval-metrics; expect_err "template"
[ -e x.h5 ] && fail "a failed run left x.h5"
expect_no_temporaries .
echo "ok (errors)"
