# MSAE end to end on a tiny synthetic bumps surface: train-msae (threads, resume, separate,
# splits), recon-msae + eval-metrics, extract-components, prune-components, bad input: the
# properties of the results. Their stored expected numbers are the golden-file cases under
# tests/golden/.
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

synth-meshseq -q --kind bumps --frames 40 --resolution 8 --seed 2 -o bumps.h5
obj2acap -q bumps.h5 -o data.h5
tiny=(--kz 3,2 --batch 16 --print-every 10 --seed 3)

# --- training: model file, log, thread independence
train-msae -q "${tiny[@]}" --iterations 30 --threads 1 data.h5 -o m.h5
h5check -q --kind msae-model m.h5
train-msae -q "${tiny[@]}" --iterations 30 --threads 2 data.h5 -o m2.h5
for obj in /params /optimizer/m /training/log /geodesic/distances; do
  run h5diff m.h5 m2.h5 $obj; expect_rc 0
done
log=$(h5_data m.h5 /training/log %.9g | tr -c '0-9.e+-' ' ')
read -r -a v <<<"$log"
[ "${#v[@]}" = 15 ] || fail "training log has ${#v[@]} numbers, expected 3 rows x 5"
awk -v a="${v[1]}" -v b="${v[11]}" 'BEGIN { exit !(b < a) }' || fail "loss did not fall: ${v[1]} -> ${v[11]}"
# the paper's sequence split: every 10th of 40 frames trains (4), 36 are held out
[ "$(h5dump -H -d /split/train m.h5 | grep -o 'DATASPACE  SIMPLE { ( [0-9]* )' | grep -o '[0-9]*')" = 4 ] ||
  fail "expected 4 training shapes"
echo "ok (train, threads: loss ${v[1]} -> ${v[11]})"

# --- collapse warned of: the paper's form spends this tiny set's three level-0 components on the
# mean deformation (codes nearly constant over the training shapes, decoded over the whole mesh):
# a warning at each loss line while it lasts and one at the end, naming the remedies and the
# report, and the model file records it. Mean-centred, with Omega's proximal step, it ends whole.
train-msae "${tiny[@]}" --paper-form --iterations 30 data.h5 -o collapsed.h5 2>collapsed.err
n=$(grep -c "warning: level 0's 3 components have collapsed (.*carrying a near-constant code" collapsed.err) || true
[ "$n" = 3 ] || fail "expected a collapse warning at each of 3 loss lines, got $n: $(cat collapsed.err)"
tail -n 2 collapsed.err | head -n 1 | grep -q "warning: the trained model (collapsed since iteration 10): .*try .*--centre-features.*; extract-components --report collapsed.h5 data.h5" ||
  fail "no final collapse line naming the remedy and the report: $(tail -n 3 collapsed.err)"
h5dump -a /training/log/collapse collapsed.h5 | grep -q "near-constant code" || fail "the model file does not record the collapse"
h5check -q --kind msae-model collapsed.h5
train-msae "${tiny[@]}" --paper-form --centre-features --support proximal --iterations 300 data.h5 -o centred.h5 2>centred.err
tail -n 3 centred.err | grep -q "collapse" && fail "the centred model still ends collapsed: $(tail -n 3 centred.err)"
h5dump -a /training/log/collapse centred.h5 2>/dev/null | grep -q "have collapsed" && fail "centred.h5 records a collapse at its end"
echo "ok (collapse: $n warnings, recorded; none at the end when centred)"

# --- the defaults (issue 65) and --paper-form: the paper's values for every option not given
cfg() { h5dump -a "/config/$2" "$1" | sed -n 's/^ *(0): \(.*\)$/\1/p' | tr -d '"' | paste -sd' '; }
train-msae -q --iterations 1 --batch 4 data.h5 -o defaults.h5
train-msae -q --iterations 1 --batch 4 --paper-form --synthetic 4 data.h5 -o paper.h5
[ "$(cfg defaults.h5 init) $(cfg defaults.h5 centre_features) $(cfg defaults.h5 support) $(cfg defaults.h5 synthetic)" = "local 1 proximal 16" ] &&
  h5dump -a /config/kz defaults.h5 | grep -q "10, 50" ||
  fail "the defaults: $(cfg defaults.h5 init) $(cfg defaults.h5 centre_features) $(cfg defaults.h5 support) $(cfg defaults.h5 synthetic)"
[ "$(cfg paper.h5 init) $(cfg paper.h5 centre_features) $(cfg paper.h5 support) $(cfg paper.h5 synthetic)" = "glorot 0 soft 4" ] &&
  h5dump -a /config/kz paper.h5 | grep -q "10, 5$" ||
  fail "--paper-form (an explicit --synthetic kept): $(cfg paper.h5 init) $(cfg paper.h5 centre_features) $(cfg paper.h5 support) $(cfg paper.h5 synthetic)"
[ "$(cfg paper.h5 started_rate)" = 1 ] || fail "--paper-form's --started-rate: $(cfg paper.h5 started_rate)"
train-msae -q --iterations 1 --batch 4 --no-centre-features data.h5 -o uncentred.h5
[ "$(cfg uncentred.h5 centre_features)" = 0 ] || fail "--no-centre-features kept the mean centring"
# --lr-warmup: recorded (an older file reads 0), the first step at lr/N, a negative one refused
train-msae -q --iterations 1 --batch 4 --lr-warmup 100 data.h5 -o warm.h5
[ "$(cfg warm.h5 lr_warmup)" = 100 ] || fail "--lr-warmup not recorded: $(cfg warm.h5 lr_warmup)"
[ "$(cfg defaults.h5 lr_warmup)" = 0 ] || fail "the default warm-up: $(cfg defaults.h5 lr_warmup)"
run h5diff -q defaults.h5 warm.h5 /params; expect_rc 1  # the first step 100 times smaller
run train-msae -q --iterations 1 --lr-warmup -1 data.h5 -o bad.h5
expect_rc 2; expect_err "lr-warmup"
echo "ok (defaults, --paper-form, --no-centre-features, --lr-warmup)"

# --- --init local: level 0 starts as the training shapes' SPLOCS components (orthonormalised),
# so before any step AE0 reconstructs the test shapes near SPLOCS-on-ACAP's least squares with as
# many components, where the random start reconstructs little more than the mean.
erms_of() { sed -n 's/^ *"erms": \([0-9.e+-]*\).*/\1/p' "$1"; }
for init in local glorot; do
  train-msae -q "${tiny[@]}" --init "$init" --iterations 0 data.h5 -o start-$init.h5
  recon-msae -q --levels 1 start-$init.h5 data.h5 -o start-$init-r.h5
  eval-metrics -q start-$init-r.h5 data.h5 --json start-$init.json >/dev/null
done
[ "$(cfg start-local.h5 init)" = local ] || fail "--init local not recorded: $(cfg start-local.h5 init)"
fit-baseline -q --method splocs-acap --components 3 start-local.h5 data.h5 -o splocs3.h5
eval-metrics -q splocs3.h5 data.h5 --json splocs3.json >/dev/null
local0=$(erms_of start-local.json) random0=$(erms_of start-glorot.json) splocs3=$(erms_of splocs3.json)
awk -v l="$local0" -v r="$random0" -v s="$splocs3" 'BEGIN { exit !(l < 0.7 * r && l < 1.4 * s) }' ||
  fail "--init local at iteration 0: E_rms $local0 (random start $random0, SPLOCS on ACAP features $splocs3)"
# --init local-all starts level 1's blocks the same way, each on its share of level 0's residual:
# level 0 as with local, and the two levels together nearer the shapes than local's random level 1.
train-msae -q "${tiny[@]}" --init local-all --iterations 0 data.h5 -o start-all.h5
for m in local all; do
  recon-msae -q --levels 2 start-$m.h5 data.h5 -o start-$m-2.h5
  eval-metrics -q start-$m-2.h5 data.h5 --json start-$m-2.json >/dev/null
done
recon-msae -q --levels 1 start-all.h5 data.h5 -o start-all-1.h5
eval-metrics -q start-all-1.h5 data.h5 --json start-all-1.json >/dev/null
[ "$(erms_of start-all-1.json)" = "$local0" ] || fail "local-all's level 0 differs from local's: $(erms_of start-all-1.json) vs $local0"
two_local=$(erms_of start-local-2.json) two_all=$(erms_of start-all-2.json)
awk -v a="$two_all" -v l="$two_local" 'BEGIN { exit !(a < 0.95 * l) }' ||
  fail "--init local-all, two levels at iteration 0: E_rms $two_all, local's $two_local"
echo "ok (--init local: E_rms $local0 before training; random start $random0, SPLOCS $splocs3; two levels: local $two_local, local-all $two_all)"

# --- resume: any model file is a checkpoint; the result equals an uninterrupted run
train-msae -q "${tiny[@]}" --iterations 20 data.h5 -o m20.h5
train-msae -q "${tiny[@]}" --iterations 30 --resume --checkpoint m20.h5 data.h5 -o resumed.h5
for obj in /params /optimizer/m /optimizer/v /rng/state /training/log; do
  run h5diff m.h5 resumed.h5 $obj; expect_rc 0
done
# a checkpoint taken before the first loss line (SIGTERM early in a run) keeps the log's columns,
# the validation shapes' E_rms included
long=(--kz 3,2 --batch 16 --seed 3 --validation-fraction 0.2 --print-every 100000000)
# (the signal comes once training runs, after its first pace line, however slow the set-up)
train-msae "${long[@]}" --iterations 100000000 data.h5 -o never.h5 --checkpoint early.h5 2>early.err &
wait_for early.err "s/iteration so far" 120
kill -TERM $!
wait $! || true
[ -f early.h5 ] || fail "SIGTERM left no checkpoint"
n=$(h5dump -a /iteration early.h5 | sed -n 's/.*(0): \([0-9]*\).*/\1/p')
train-msae -q "${long[@]}" --iterations $((n + 5)) --resume --checkpoint early.h5 data.h5 -o late.h5
h5dump -A -d /training/log late.h5 | grep -q validation_erms || fail "the resumed log lost validation_erms"
run train-msae "${tiny[@]}" --kz 3,3 --iterations 30 --resume --checkpoint m20.h5 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "made with --kz 3,2, this run has 3,2,3,3"
echo "ok (resume)"

# A training option: thread-independent, resumable (bit-identical), stored as /config/ATTR, a
# different model from m.h5's, and its bad value refused. option_run NAME ATTR VALUE BAD OPTION...
option_run() {
  local name=$1 attr=$2 value=$3 bad=$4; shift 4
  train-msae -q "${tiny[@]}" --iterations 30 "$@" --threads 1 data.h5 -o "$name.h5"
  train-msae -q "${tiny[@]}" --iterations 30 "$@" --threads 2 data.h5 -o "${name}2.h5"
  train-msae -q "${tiny[@]}" --iterations 20 "$@" data.h5 -o "${name}20.h5"
  train-msae -q "${tiny[@]}" --iterations 30 "$@" --resume --checkpoint "${name}20.h5" data.h5 -o "$name-r.h5"
  for obj in /params /optimizer/m /rng/state /training/log; do
    run h5diff "$name.h5" "${name}2.h5" $obj; expect_rc 0
    run h5diff "$name.h5" "$name-r.h5" $obj; expect_rc 0
  done
  run h5diff -q m.h5 "$name.h5" /params; expect_rc 1
  h5dump -a "/config/$attr" "$name.h5" | grep -q "(0): $value" || fail "/config/$attr is not $value"
  run train-msae "${tiny[@]}" "--${attr//_/-}" "$bad" data.h5 -o x.h5
  expect_rc 2; expect_one_error_line train-msae; expect_err "${attr//_/-}"
}

# --synthetic: recombined shapes in every batch
option_run syn synthetic 4 -1 --synthetic 4
echo "ok (synthetic shapes)"
# --started-rate: the started level's components step slower, so after 30 iterations they lie
# nearer their start (start-local.h5, the same options at iteration 0) than at the full rate (1);
# the default, 0.01, nearer still
option_run slowstart started_rate 0.1 0 --started-rate 0.1
option_run fullstart started_rate 1 0 --started-rate 1
c_distance() {
  paste <(h5_data "$1" /params/ae0.0.C %.9g | tr -c '0-9.e+-' ' ' | tr -s ' ' '\n' | grep .) \
    <(h5_data "$2" /params/ae0.0.C %.9g | tr -c '0-9.e+-' ' ' | tr -s ' ' '\n' | grep .) |
    awk '{ d += ($1 - $2) ^ 2 } END { print sqrt(d) }'
}
slow=$(c_distance slowstart.h5 start-local.h5) full=$(c_distance fullstart.h5 start-local.h5)
default=$(c_distance m.h5 start-local.h5)
awk -v s="$slow" -v f="$full" -v d="$default" 'BEGIN { exit !(s < 0.5 * f && d < s) }' ||
  fail "--started-rate: C moved $slow from its start at 0.1, $full at the full rate, $default at the default"
[ "$(cfg defaults.h5 started_rate)" = 0.01 ] || fail "the default --started-rate: $(cfg defaults.h5 started_rate)"
echo "ok (--started-rate: level 0's C moved $default from its start at the default 0.01, $slow at 0.1, $full at the full rate)"
# --start-scale: the started block's convolutions start as S x I (and C as the components / S);
# with the decoder's first tanh (--decoder-fc tanh, the default) it is refused
option_run scaled start_scale 0.1 0 --decoder-fc linear --start-scale 0.1
train-msae -q "${tiny[@]}" --iterations 0 --decoder-fc linear --start-scale 0.1 data.h5 -o scaled0.h5
point=$(h5_data scaled0.h5 /params/ae0.0.conv.point %.6g | tr -c '0-9.e+-' ' ' | tr -s ' ' '\n' | grep . |
  awk 'NR % 10 == 1 { d = d " " $1 } NR % 10 != 1 { o += $1 * $1 } END { print d, o }')
[ "$point" = " 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0" ] || fail "--start-scale 0.1's point weights: $point"
[ "$(cfg defaults.h5 start_scale)" = 1 ] || fail "the default --start-scale: $(cfg defaults.h5 start_scale)"
run train-msae "${tiny[@]}" --start-scale 0.1 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-msae; expect_err "decoder-fc linear"
echo "ok (--start-scale)"
# --proximal-cap: the proximal step's shrink per step is capped (recorded, resumable, 0 = none)
option_run capped proximal_cap 1 -1 --proximal-cap 1
[ "$(cfg defaults.h5 proximal_cap)" = 0 ] || fail "the default --proximal-cap: $(cfg defaults.h5 proximal_cap)"
echo "ok (--proximal-cap)"
# --lambda-whole: the whole reconstruction's MSE in the loss; a checkpoint without it is refused
option_run whole lambda_whole 10 -1 --lambda-whole 10
run train-msae "${tiny[@]}" --iterations 30 --resume --checkpoint whole20.h5 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "lambda"
echo "ok (whole reconstruction's loss)"

# --- separate training, no attention, three levels, a validation part, a collection split
train-msae "${tiny[@]}" --iterations 20 --separate data.h5 -o sep.h5 2>sep.err
grep -q "level 1 from iteration 11" sep.err || fail "separate training did not switch levels: $(cat sep.err)"
train-msae -q "${tiny[@]}" --iterations 10 --no-attention data.h5 -o plain.h5
# --support proximal: Omega's proximal step leaves groups C_k,i (9 weights) exactly zero; the soft
# penalty's gradient at the same weight leaves none (a large weight: in 30 iterations on this tiny
# set the reconstruction's gradient outweighs the default one everywhere)
zero_groups() {
  h5_data "$1" "$2" %.9g | tr -c '0-9.e+-' ' ' |
    awk '{ for (i = 1; i <= NF; i++) { n++; if ($i != 0) nz = 1; if (n % 9 == 0) { z += !nz; nz = 0 } } } END { print z + 0 }'
}
train-msae -q "${tiny[@]}" --iterations 30 --lambda-sparse 1000 --support soft data.h5 -o soft.h5
train-msae -q "${tiny[@]}" --iterations 30 --lambda-sparse 1000 --support proximal data.h5 -o prox.h5
h5check -q --kind msae-model prox.h5
for c in /params/ae0.0.C /params/ae1.0.C; do
  [ "$(zero_groups soft.h5 $c)" = 0 ] || fail "soft support: $c has $(zero_groups soft.h5 $c) zero groups"
  [ "$(zero_groups prox.h5 $c)" -gt 0 ] || fail "proximal support: $c has no zero group"
done
echo "ok (proximal support: $(zero_groups prox.h5 /params/ae0.0.C) of 243 level-0 groups zero)"
[ "$(h5dump -H -d '/params/ae1.0.C' plain.h5 | grep -o 'SIMPLE { ( [0-9, ]* )' | tr -dc '0-9,')" = "6,729" ] ||
  fail "no attention: one level-1 block with 3 x 2 components expected"
train-msae -q --levels 3 --kz 2,2,2 --batch 8 --iterations 10 --validation-fraction 0.25 data.h5 -o three.h5
h5dump -a /training/log/columns three.h5 | grep -q "validation" || fail "validation column missing"
[ "$(h5dump -H -d /split/validation three.h5 | grep -o 'SIMPLE { ( [0-9]* )' | grep -o '[0-9]*')" = 9 ] ||
  fail "25% of 36 held-out shapes should validate"
train-msae -q "${tiny[@]}" --iterations 10 --split collection data.h5 -o coll.h5
[ "$(h5dump -H -d /split/train coll.h5 | grep -o 'SIMPLE { ( [0-9]* )' | grep -o '[0-9]*')" = 20 ] ||
  fail "collection split: half of 40 should train"
names=$(h5_data data.h5 /frames/names | grep -o '"[^"]*"' | tr -d '"')
printf '%s\n# a comment\n\n5\n%s\n' "$(sed -n 1p <<<"$names")" "$(sed -n 8p <<<"$names")" > train.txt
train-msae -q "${tiny[@]}" --iterations 10 --train train.txt data.h5 -o lists.h5
[ "$(h5_data lists.h5 /split/train | tr -dc '0-9 ,' | tr -s ' ,' ' ' | xargs)" = "0 5 7" ] ||
  fail "list split: $(h5dump -d /split/train lists.h5)"
echo "ok (separate, no attention, levels, validation, splits)"

# --- recon-msae and eval-metrics: one frame per held-out shape, paired by /frames/source
recon-msae -q m.h5 data.h5 -o recon.h5
h5check -q --kind acap recon.h5
eval-metrics -q recon.h5 data.h5 --json recon.json > /dev/null
grep -q '"frame_pairs": 36,' recon.json || fail "36 frame pairs expected: $(head -c 300 recon.json)"
erms=$(sed -n 's/^ *"erms": \([0-9.e+-]*\).*/\1/p' recon.json)
awk -v e="$erms" 'BEGIN { exit !(e > 0 && e < 1000) }' || fail "E_rms '$erms'"
recon-msae -q --levels 1 m.h5 data.h5 -o recon1.h5
# --levels all (what --help shows as the default) is every level: the default's features
recon-msae -q --levels all m.h5 data.h5 -o recon-all.h5
[ "$(h5dump -d /features/normalized recon-all.h5 | sed 1d)" = "$(h5dump -d /features/normalized recon.h5 | sed 1d)" ] ||
  fail "--levels all differs from the default"
[ "$(h5dump -d /features/normalized recon1.h5 | sed 1d)" != "$(h5dump -d /features/normalized recon.h5 | sed 1d)" ] ||
  fail "--levels 1 equals every level"
run recon-msae m.h5 data.h5 -o x.h5 --levels most
expect_rc 2; expect_err "--levels = most"
recon-msae -q --part train m.h5 data.h5 -o recon-train.h5
[ "$(h5dump -H -d /frames/source recon-train.h5 | grep -o 'SIMPLE { ( [0-9]* )' | grep -o '[0-9]*')" = 4 ] ||
  fail "--part train: 4 shapes"
echo "ok (recon)"

# --- components: extract, prune, decodable by acap2obj
extract-components -q m.h5 data.h5 -o comps.h5 --acap comps-acap.h5
h5check -q --kind components comps.h5
h5check -q --kind acap comps-acap.h5
[ "$(h5dump -H -d /level1/features comps.h5 | grep -o 'SIMPLE { ( [0-9, ]* )' | tr -dc '0-9,')" = "6,81,9" ] ||
  fail "level 1: 3 blocks x 2 components"
acap2obj -q comps-acap.h5 -o comps-obj
[ "$(ls comps-obj | wc -l)" = 9 ] || fail "9 component meshes expected: $(ls comps-obj)"
prune-components comps.h5 -o kept.h5 --eps2 0 --json all.json > all.txt
grep -q "level 1: 6 kept, 0 dropped" all.txt || fail "eps2 0 keeps everything: $(cat all.txt)"
prune-components comps.h5 -o none.h5 --eps2 1e9 > none.txt
grep -q "level 0: 0 kept, 3 dropped" none.txt || fail "a huge eps2 drops everything: $(cat none.txt)"
run prune-components comps.h5 -o x.h5 --eps2 1e9 --acap x-acap.h5
expect_rc 1; expect_one_error_line prune-components; expect_err "nothing to write"
[ ! -e x.h5 ] && [ ! -e x-acap.h5 ] || fail "files written after an error"
# where the components are: one row per planted region (2 coarse, 4 fine), IoU in [0, 1]
eval-metrics kept.h5 bumps.h5 > loc.txt
[ "$(awk '$2 == "coarse" || $2 == "fine" { if ($NF < 0 || $NF > 1) bad = 1; n++ } END { print bad ? -1 : n }' loc.txt)" = 6 ] ||
  fail "localization table: $(cat loc.txt)"
eval-metrics kept.h5 bumps.h5 --json loc.json > /dev/null
grep -q '"iou"' loc.json || fail "localization JSON: $(cat loc.json)"
echo "ok (components)"

# --- bad input: one line, nothing written
synth-meshseq -q --kind bumps --frames 12 --resolution 6 --seed 2 -o other.h5
obj2acap -q other.h5 -o other-acap.h5
run recon-msae m.h5 other-acap.h5 --part all -o x.h5
expect_rc 1; expect_one_error_line recon-msae; expect_err "another template"
run eval-metrics kept.h5 other.h5
expect_rc 1; expect_one_error_line eval-metrics; expect_err "vertices"
run eval-metrics kept.h5 data.h5
expect_rc 1; expect_one_error_line eval-metrics; expect_err "planted regions"
run extract-components m.h5 other-acap.h5 -o x.h5
expect_rc 1; expect_one_error_line extract-components; expect_err "another template"
run train-msae "${tiny[@]}" --every 40 data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "1 training shape"
printf 'no-such-frame\n' > bad.txt
run train-msae "${tiny[@]}" --train bad.txt data.h5 -o x.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "bad.txt:1"
run train-msae --kz 10,5 --d 0.4 data.h5 -o x.h5
expect_rc 2; expect_one_error_line train-msae; expect_err "one value per level"
run recon-msae --levels 3 m.h5 data.h5 -o x.h5
expect_rc 2; expect_one_error_line recon-msae; expect_err "levels must be in 1..2"
run recon-msae comps.h5 data.h5 -o x.h5
expect_rc 1; expect_one_error_line recon-msae; expect_err "msae-model"
# SPLOCS on positions writes position components, which prune-components refuses by name
run fit-baseline --method splocs m.h5 data.h5 -o sp.h5 --components-out sp-comps.h5
expect_rc 0
run prune-components sp-comps.h5 -o x.h5
expect_rc 1; expect_one_error_line prune-components; expect_err "needs ACAP components"
# meshes without ACAP features (synth-meshseq's positions): refused before any work, saying what to run
run train-msae bumps.h5 -o x.h5
expect_rc 1; expect_one_error_line train-msae; expect_err "has no /features/normalized; run obj2acap"
[ ! -e x.h5 ] || fail "x.h5 written after an error"
expect_no_temporaries .
echo "ok (bad input)"
