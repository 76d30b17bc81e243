# inspect-bdlstm: the latent report of a BD-LSTM. An untrained network of the paper's form predicts no change (its
# last decoder layer starts at zero), so every latent input gives exactly zero motion's error; the
# KL table has one sorted row per latent dimension; bad inputs give one error line.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

synth-meshseq -q --frames 60 --resolution 4 --periods 2 -o finger.h5
obj2acap -q finger.h5 -o data.h5
tiny=(--window 8 --batch 2 --latent 6 --hidden 8 --lstm-layers 1 --print-every 10 --seed 3)
train-bdlstm -q "${tiny[@]}" --iterations 0 --paper-form data.h5 -o untrained.h5
inspect-bdlstm untrained.h5 data.h5 --initial 2 --length 4 --tsv u.tsv > u.txt
grep -q "0 iterations, latent 6 (VAE encoder with KL)" u.txt || fail "header: $(cat u.txt)"
mean=$(sed -n 's/^ *z = encoder mean *//p' u.txt)
zero=$(sed -n 's/^ *zero motion *//p' u.txt)
[ -n "$mean" ] && [ "$mean" = "$zero" ] || fail "an untrained network should predict zero motion: '$mean' vs '$zero'"
# KL block: 6 rows, largest first; error block: 4 steps x (step + 4 columns)
# KL block: 6 rows, largest first; error block: 4 steps x (step + 4 columns); training log: none
# for an untrained model
awk '/^# kl_per/ { b = 1; next } /^# error/ { b = 2; next } /^# training_log/ { b = 3; next } NF == 0 { next }
     b == 1 { n1++; if (n1 > 1 && $2 > prev + 1e-12) bad = 1; prev = $2 }
     b == 2 { n2++; if (NF != 5) bad = 1 }
     b == 3 { n3++ }
     END { exit !(n1 == 6 && n2 == 4 && n3 == 0 && !bad) }' u.tsv || fail "unexpected TSV: $(cat u.tsv)"

train-bdlstm -q "${tiny[@]}" --iterations 30 data.h5 -o m.h5
inspect-bdlstm m.h5 data.h5 --part test --initial 1 --length 3 --tsv t.tsv > t.txt
grep -q "windows of the test part, 1 given frames: .* at step 1 / 3 and" t.txt || fail "test part: $(cat t.txt)"
# the training log: 3 rows (iterations 10, 20, 30) of 7 columns (the last: the default early
# stopping's error on its part)
[ "$(awk '/^# training_log/ { b = 1; next } b && NF == 7 { n++ } END { print n }' t.tsv)" = 3 ] ||
  fail "training log block: $(cat t.tsv)"
train-bdlstm -q "${tiny[@]}" --iterations 10 --no-kl data.h5 -o nokl.h5
inspect-bdlstm nokl.h5 data.h5 --length 3 | grep -q "deterministic encoder" || fail "no-KL model not reported as such"

# --- a validation part: stored in the model, cases and probes drawn from it
train-bdlstm -q "${tiny[@]}" --iterations 10 --validation-fraction 0.25 --checkpoint val-ck.h5 data.h5 -o val.h5
val=$(h5dump -y -w 0 -d /split/validation val.h5 | awk '/DATA \{/ { d = 1; next } d && /\}/ { exit } d { gsub(/,/, " "); print $1, $2 }')
read -r vb ve <<<"$val"
[ $(( ve - vb )) = 15 ] || fail "validation part of 25% of 60 frames expected, got '$val'"
gen-bdlstm -q val.h5 data.h5 --test-every 1 --part validation --initial 1 --length 3 -o valpred.h5
h5dump -y -w 0 -d /frames/source valpred.h5 | awk -v b="$vb" -v e="$ve" '/DATA \{/ { d = 1; next } d && /\}/ { exit }
  d { gsub(/,/, " "); for (i = 1; i <= NF; i++) if ($i < b || $i >= e) bad = 1; n += NF } END { exit !(n > 0 && !bad) }' ||
  fail "validation cases reach outside frames $vb-$ve"
inspect-bdlstm val.h5 data.h5 --part validation --initial 1 --length 3 | grep -q "windows of the validation part" ||
  fail "inspect --part validation"
run train-bdlstm -q "${tiny[@]}" --iterations 20 --validation-fraction 0.1 --checkpoint val-ck.h5 --resume data.h5 -o v2.h5
expect_rc 1; expect_one_error_line train-bdlstm; expect_err "validation-fraction"
run gen-bdlstm m.h5 data.h5 --test-every 1 --part validation -o x.h5
expect_rc 1; expect_one_error_line gen-bdlstm; expect_err "no validation part"

run inspect-bdlstm m.h5 data.h5 --part middle
expect_rc 2; expect_err "^inspect-bdlstm: error: --part: middle not in [{]train,validation,test[}]"
synth-meshseq -q --frames 20 --resolution 4 --periods 2 -o short.h5
obj2acap -q short.h5 -o short-acap.h5
run inspect-bdlstm m.h5 short-acap.h5
expect_rc 1; expect_one_error_line inspect-bdlstm; expect_err "not the data the model was trained on"
run inspect-bdlstm m.h5 data.h5 --length 100
expect_rc 1; expect_one_error_line inspect-bdlstm; expect_err "no window"
echo "ok"
