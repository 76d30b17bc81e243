# ActGAN end to end on tiny synthetic actions: skel2h5 clips, train-actgan (pre-training + GAN,
# thread independence, bit-exact resume, determinism per seed), a short training moves the
# generated poses towards the data (MMD falls), gen-actgan (classes, mixture, latents),
# classify-actions, eval-metrics on skeleton files, and bad input. Stored numbers: tests/golden/.
DF_ROOT=$(cd "$(dirname "$0")/../.." && pwd)
source "$(dirname "$0")/lib.sh"
: "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR

synth-actions -q --classes walk,wave,squat --per-class 8 --frames 24 --seed 1 -o raw.h5
skel2h5 -q raw.h5 --length 12 --clip-stride 6 --test-fraction 0.25 --seed 2 -o clips.h5
# --paper-form: the sections below exercise the paper's BiLSTM discriminator and both smoothness
# terms, as before the defaults changed (the defaults' own section follows)
tiny=(--paper-form --noise 4 --latent 3 --hidden 16 --fc 32 --batch 8 --pretrain-batch 16 --print-every 10 --seed 3)
# A model's /config attribute: attr NAME FILE (a number), sattr NAME FILE (a string).
attr() { h5dump -a /config/$1 $2 | grep -A1 DATA | tail -1 | sed 's/.*: *//'; }
sattr() { h5dump -a /config/$1 -y $2 | sed -n 's/^ *"\(.*\)"$/\1/p'; }

# --- thread independence and resume
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --threads 1 clips.h5 -o m1.h5
h5check -q --kind actgan-model m1.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --threads 2 clips.h5 -o m2.h5
for obj in /params /optimizers /rng/state /training/log; do
  run h5diff m1.h5 m2.h5 $obj; expect_rc 0
done
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 5 clips.h5 -o m-half.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --resume --checkpoint m-half.h5 clips.h5 -o resumed.h5
for obj in /params /optimizers /rng/state /training/log; do
  run h5diff m1.h5 resumed.h5 $obj; expect_rc 0
done
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --gamma 0.5 --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "made with --gamma 0.1, this run has 0.5"
echo "ok (threads, resume)"

# --- the defaults (the critic, 5 critic steps, Omega's pose term, h_1 ~ N(0, I)) and --paper-form
# (the BiLSTM, 1 step, both terms, uniform), under which options given explicitly still win
small=(--noise 4 --latent 3 --hidden 16 --fc 32 --batch 8 --pretrain-batch 16 --seed 3 --pretrain-iterations 2 --iterations 2)
train-actgan -q "${small[@]}" clips.h5 -o m-defaults.h5
train-actgan -q "${small[@]}" --paper-form --d-steps 3 clips.h5 -o m-paper.h5
form_of() { echo "$(sattr discriminator $1) $(attr d_steps $1) $(sattr smoothness $1) $(sattr start $1)"; }
[ "$(form_of m-defaults.h5)" = "critic 5 action normal" ] || fail "defaults: $(form_of m-defaults.h5)"
[ "$(form_of m-paper.h5)" = "bilstm 3 both uniform" ] || fail "--paper-form --d-steps 3: $(form_of m-paper.h5)"
echo "ok (defaults: the critic, 5 steps, smoothness of poses, h_1 ~ N(0, I); --paper-form: the BiLSTM, both terms, uniform)"

# --- --freeze-decoder: the GAN phase keeps the pre-trained decoder as it is
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 0 clips.h5 -o pretrained.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --freeze-decoder clips.h5 -o m-frozen.h5
for p in gen.decoder.0.weight gen.decoder.1.bias; do
  run h5diff pretrained.h5 m-frozen.h5 /params/$p; expect_rc 0
  run h5diff -q pretrained.h5 m1.h5 /params/$p; expect_rc 1
done
run h5diff -q pretrained.h5 m-frozen.h5 /params/gen.lstm.wx; expect_rc 1
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --freeze-decoder --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "freeze-decoder"
run train-actgan "${tiny[@]}" --generator pose --pretrain-iterations 0 --iterations 2 --freeze-decoder clips.h5 -o x.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "no decoder to freeze"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (frozen decoder)"

# --- --step-init small: the generator's output layer starts at 0.01 x its Glorot draw; stored,
# checked on --resume, refused for the pose baseline
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 0 --step-init small clips.h5 -o m-small.h5
[ "$(sattr step_init m-small.h5)" = small ] || fail "step_init not stored"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --step-init small --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "step-init"
run train-actgan "${tiny[@]}" --generator pose --pretrain-iterations 0 --iterations 2 --step-init small clips.h5 -o x.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "step-init"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (step init)"

# --- --start normal: each sequence's latent starts at h_1 ~ N(0, I) instead of U(-1, 1); stored,
# used by gen-actgan (first latents beyond +-1 appear with it and never without), checked on
# --resume, refused when unknown
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 0 --start normal clips.h5 -o m-normal.h5
[ "$(sattr start m-normal.h5)" = normal ] || fail "start not stored"
[ "$(sattr start m1.h5)" = uniform ] || fail "start is not uniform under --paper-form"
beyond_one() { awk -F'\t' '!/^#/ && $2 == 0 { for (i = 3; i <= NF; ++i) n += ($i > 1 || $i < -1) } END { print n + 0 }' "$1"; }
gen-actgan -q --count 20 --latents lat-normal.tsv m-normal.h5 -o gen-normal.h5
gen-actgan -q --count 20 --latents lat-uniform.tsv m1.h5 -o gen-uniform.h5
n_normal=$(beyond_one lat-normal.tsv) n_uniform=$(beyond_one lat-uniform.tsv)
[ "$n_uniform" = 0 ] && [ "$n_normal" -gt 20 ] ||
  fail "first latents beyond +-1: $n_normal of 180 with --start normal (about 57 expected), $n_uniform without (0 expected)"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --start normal --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "start"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 2 --start sideways clips.h5 -o x.h5
expect_rc 2; expect_err "start: sideways not in"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (start: $n_normal of 180 first latents beyond +-1 from N(0, I), $n_uniform from U(-1, 1))"

# --- --disc-input motion --disc-pool all (the authors' discriminator): trains, stored, its head
# reads all 12 steps of [x_t, x_t - x_{t-1}, y] (2 x 16 x 12 inputs), checked on --resume;
# gen-actgan and classify-actions read the model (the classifier keeps any length)
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 5 --disc-input motion --disc-pool all clips.h5 -o m-authors.h5
h5check -q --kind actgan-model m-authors.h5
for a in disc_input:motion disc_pool:all; do
  [ "$(sattr ${a%%:*} m-authors.h5)" = "${a#*:}" ] || fail "${a%%:*} not stored"
done
h5dump -H -d /params/disc.head.0.weight m-authors.h5 | grep -q "( 384, 32 )" || fail "the head does not read every step"
gen-actgan -q --seed 4 --count 2 --length 20 m-authors.h5 -o gen-authors.h5
classify-actions -q m-authors.h5 gen-authors.h5 > /dev/null
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-pool all --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "disc-pool"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-input motion --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "disc-input"
run train-actgan "${tiny[@]}" --disc-pool mean clips.h5 -o x.h5
expect_rc 2; expect_err "disc-pool: mean not in"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (authors' discriminator)"

# --- --disc-noise (instance noise on what the discriminator sees): stored, changes the training
# (same seeds as m1.h5), thread-independent, checked on --resume, not negative
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-noise 0.2 --threads 1 clips.h5 -o m-noise1.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-noise 0.2 --threads 2 clips.h5 -o m-noise2.h5
run h5diff m-noise1.h5 m-noise2.h5 /params; expect_rc 0
run h5diff -q m1.h5 m-noise1.h5 /params/gen.lstm.wx; expect_rc 1
[ "$(attr disc_noise m-noise1.h5)" = 0.2 ] || fail "disc_noise not stored"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-noise 0.2 --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "disc-noise"
run train-actgan "${tiny[@]}" --disc-noise -1 clips.h5 -o x.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "disc-noise"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (instance noise)"

# --- --disc-lr (the discriminator's own learning rate): stored (the GAN's lr when not given),
# changes the training, checked on --resume, not negative
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-lr 1e-5 clips.h5 -o m-dlr.h5
run h5diff -q m1.h5 m-dlr.h5 /params/gen.lstm.wx; expect_rc 1
[ "$(attr disc_lr m-dlr.h5)" = 1e-05 ] || fail "disc_lr not stored: $(attr disc_lr m-dlr.h5)"
[ "$(attr disc_lr m1.h5)" = "$(attr lr m1.h5)" ] || fail "disc_lr is not lr by default"
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 20 --disc-lr 1e-5 --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "disc-lr"
run train-actgan "${tiny[@]}" --disc-lr -1 clips.h5 -o x.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "disc-lr"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (discriminator learning rate)"

# --- --discriminator critic (a Wasserstein critic of whole clips with the gradient penalty):
# stored, its input T·P + C wide, thread-independent, resumes bit-exactly, read by gen-actgan;
# refused with the BiLSTM's options and on --resume of a BiLSTM checkpoint
crit=(--discriminator critic --d-steps 2 --pretrain-iterations 10)
train-actgan -q "${tiny[@]}" "${crit[@]}" --iterations 20 --threads 1 clips.h5 -o m-crit1.h5
train-actgan -q "${tiny[@]}" "${crit[@]}" --iterations 20 --threads 2 clips.h5 -o m-crit2.h5
h5check -q --kind actgan-model m-crit1.h5
run h5diff m-crit1.h5 m-crit2.h5 /params; expect_rc 0
train-actgan -q "${tiny[@]}" "${crit[@]}" --iterations 5 clips.h5 -o m-crit-half.h5
train-actgan -q "${tiny[@]}" "${crit[@]}" --iterations 20 --resume --checkpoint m-crit-half.h5 clips.h5 -o m-crit-resumed.h5
run h5diff m-crit1.h5 m-crit-resumed.h5 /params; expect_rc 0
[ "$(sattr discriminator m-crit1.h5)" = critic ] || fail "discriminator not stored"
frames=$(attr length m-crit1.h5)
h5dump -H -d /params/disc.0.weight m-crit1.h5 | grep -q "( $((frames * 60 + 3)), " || fail "the critic does not read whole clips"
gen-actgan -q --seed 4 --count 2 m-crit1.h5 -o gen-crit.h5
run train-actgan "${tiny[@]}" "${crit[@]}" --iterations 20 --resume --checkpoint m-half.h5 clips.h5 -o x.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "discriminator"
run train-actgan "${tiny[@]}" "${crit[@]}" --disc-input motion clips.h5 -o x.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "disc-input"
run train-actgan "${tiny[@]}" --discriminator gru clips.h5 -o x.h5
expect_rc 2; expect_err "discriminator: gru not in"
[ -f x.h5 ] && fail "output written after an error"
echo "ok (clip critic)"

# --- learning: the generated poses move towards the data (MMD of generated vs real falls; the
# tiny networks' GAN is noisy, so the bound is loose: measured 0.54 -> 0.27 and 1.0 -> 0.47)
train-actgan -q "${tiny[@]}" --pretrain-iterations 0 --iterations 1 clips.h5 -o untrained.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 300 --iterations 300 clips.h5 -o trained.h5
gen-actgan -q --seed 4 --count 12 untrained.h5 -o gen0.h5
gen-actgan -q --seed 4 --count 12 trained.h5 -o gen1.h5
mmd() { eval-metrics "$1" clips.h5 --json - | sed -n "s/^  \"mmd_$2\": \([^,]*\),*\$/\1/p"; }
for kind in avg seq; do
  before=$(mmd gen0.h5 $kind) after=$(mmd gen1.h5 $kind)
  awk -v a="$before" -v b="$after" 'BEGIN { exit !(b < 0.6 * a) }' || fail "MMD_$kind did not fall: $before -> $after"
  echo "ok (learning: MMD_$kind $before -> $after)"
done

# --- the data's own level (eval-metrics --pred-subjects / --truth-subjects): some subjects' real
# clips against another's; a subject's clips against themselves leave nothing (MMD_u^2 <= 0)
run eval-metrics clips.h5 clips.h5 --pred-subjects 1,2 --truth-subjects 3; expect_rc 0
expect_out "walk +12 +6 "
own() { eval-metrics clips.h5 clips.h5 --pred-subjects "$1" --truth-subjects "$2" --json - |
  sed -n "s/^  \"mmd_seq\": \([^,]*\),*\$/\1/p"; }
others=$(own 1,2 3) self=$(own 3 3)
awk -v o="$others" -v s="$self" 'BEGIN { exit !(o > 0.01 && s <= 1e-6) }' ||
  fail "subjects 1,2 against 3: $others, 3 against itself: $self"
run eval-metrics clips.h5 clips.h5 --pred-subjects 9; expect_rc 1
expect_one_error_line eval-metrics; expect_err "subject 9 performs none of PRED"
run eval-metrics clips.h5 clips.h5 --truth-subjects 3 --all-truth; expect_rc 2
expect_one_error_line eval-metrics; expect_err "all-truth"
echo "ok (the data against itself by subject: $others; a subject against itself: $self)"

# --- generation: deterministic per seed, different across seeds; classes, mixtures, latents
gen-actgan -q --seed 4 --count 12 trained.h5 -o again.h5
run h5diff gen1.h5 again.h5 /poses; expect_rc 0
gen-actgan -q --seed 5 --count 12 trained.h5 -o other.h5
run h5diff -q gen1.h5 other.h5 /poses; expect_rc 1
gen-actgan -q --class wave --length 30 --count 2 --latents lat.tsv trained.h5 -o wave.h5
[ "$(h5dump -H -d /poses wave.h5 | grep -o 'SIMPLE { ( [0-9, ]* )' | tr -dc '0-9,')" = "60,20,3" ] ||
  fail "2 waves of 30 frames expected: $(h5dump -H -d /poses wave.h5)"
[ "$(grep -c '^wave~1' lat.tsv)" = 30 ] || fail "latents: 30 rows of wave~1 expected"
gen-actgan -q --mix walk:1,wave:3 --count 3 trained.h5 -o mix.h5
h5dump -d /sequences/names mix.h5 | grep -q '"walk+wave~2"' || fail "mixture names"
h5dump -d /sequences/label_weights mix.h5 | grep -q '(2,0): 0.25, 0.75, 0$' || fail "mixture weights: $(h5dump -d /sequences/label_weights mix.h5)"
run classify-actions trained.h5 mix.h5 --probabilities; expect_rc 0
expect_out "walk\+wave~0 +[0-9.]+ +[0-9.]+ +[0-9.]+"
# a mixture has no right answer: not scored, its probabilities printed without being asked for
run classify-actions trained.h5 mix.h5 --json mix.json; expect_rc 0
expect_out "^3 sequences generated for a mixture of classes \(walk 0.25 \+ wave 0.75\): not scored"
expect_out "^walk\+wave~2 +[0-9.]+ +[0-9.]+ +[0-9.]+  (walk|wave|squat)$"
! grep -qE '^(all|wave) +[0-9]' out.txt || fail "a mixture scored: $(cat out.txt)"
labels=$(python3 "$DF_ROOT/scripts/classified-labels" mix.json)  # the pictures' row captions, from the JSON
[[ $labels =~ ^walk\+wave~0:\ classified\ [a-z]+\ [01]\.[0-9]{2},walk\+wave~1:\ .*,walk\+wave~2:\ classified\ [a-z]+\ [01]\.[0-9]{2}$ ]] ||
  fail "classified-labels: '$labels'"
# the same verdicts as the printed table's last column
[ "$(sed -n 's/^\(walk+wave~[0-9]\) .*  \([a-z]*\)$/\1: classified \2/p' out.txt | paste -sd,)" = \
  "$(echo "$labels" | tr , '\n' | sed 's/ [0-9.]*$//' | paste -sd,)" ] || fail "classified-labels disagrees with the table: '$labels'"
echo '{"model": "m.h5"}' > noprob.json
run python3 "$DF_ROOT/scripts/classified-labels" noprob.json; expect_rc 1; expect_err "no class probabilities in noprob.json"
grep -q '"walk+wave~1": "walk 0.25 + wave 0.75"' mix.json && ! grep -q '"overall"' mix.json || fail "mixture JSON: $(cat mix.json)"
h5check -q --kind skeleton mix.h5
# scripts/pose-norms (actgan-validation's pose sizes): two positive means, first and last frame
norms=$(bash "$DF_ROOT/scripts/pose-norms" gen1.h5)
[[ $norms =~ ^[0-9]+\.[0-9]{2}\ [0-9]+\.[0-9]{2}$ ]] && awk -v a="${norms% *}" -v b="${norms#* }" 'BEGIN { exit !(a > 0 && b > 0) }' ||
  fail "pose-norms: two positive numbers expected, got '$norms'"
echo "ok (generation)"

# --- the classifier on the real test part and on generated sequences
run classify-actions trained.h5 clips.h5 --json acc.json; expect_rc 0
expect_out "clips.h5 classified by trained.h5 \([0-9]+ sequences, the test part\)"
grep -q '"overall"' acc.json || fail "no overall accuracy in the JSON"
echo "ok (classify: $(grep -o 'all .*' out.txt))"

# --- a recogniser trained alone on the real clips: FID, diversity, multimodality, accuracy
train-actgan -q --hidden 16 --fc 8 --batch 8 --seed 3 --classifier-only --pretrain-iterations 0 --iterations 150 clips.h5 -o rec.h5
rec() { eval-metrics "$1" clips.h5 --recogniser rec.h5 --json - | python3 -c "import json, sys; r = json.load(sys.stdin)['recognition']; print(r['features'], *(f'{r[w][k]:.6g}' for w in ('generated', 'real') for k in ('fid', 'diversity', 'multimodality', 'accuracy')))"; }
read -r width fid1 div1 mm1 acc1 fid_real div_real mm_real acc_real <<< "$(rec gen1.h5)"
read -r _ fid0 _ _ acc0 _ _ _ _ <<< "$(rec gen0.h5)"
[ "$width" = 8 ] || fail "the recogniser's features: 8 wide (its --fc) expected, got $width"
awk -v a="$acc_real" -v f0="$fid0" -v f1="$fid1" -v d="$div_real" -v m="$mm_real" 'BEGIN { exit !(a >= 0.5 && f1 < f0 && f1 >= 0 && d > 0 && m > 0 && m < d) }' ||
  fail "recognition: real accuracy $acc_real (>= 0.5), FID untrained $fid0 > trained $fid1 >= 0, real diversity $div_real > multimodality $mm_real > 0 expected"
run eval-metrics gen1.h5 clips.h5 --recogniser rec.h5; expect_rc 0
expect_out "^generated \(PRED\) +[0-9.e+-]+ +[0-9.e+-]+ +[0-9.e+-]+ +[01]\.[0-9]{3}$"
[ "$(rec gen1.h5)" = "$(rec gen1.h5)" ] || fail "recognition measures differ between two runs"
run eval-metrics gen1.h5 clips.h5 --recogniser m-crit1.h5; expect_rc 0  # any model with a classifier
train-actgan -q "${tiny[@]}" --no-classifier --pretrain-iterations 1 --iterations 1 clips.h5 -o nocls.h5
run eval-metrics gen1.h5 clips.h5 --recogniser nocls.h5; expect_rc 1
expect_one_error_line eval-metrics; expect_err "the recogniser has no classifier"
synth-actions -q --classes walk,kick --per-class 4 --frames 24 --seed 1 -o kick-raw.h5
skel2h5 -q kick-raw.h5 --length 12 --clip-stride 6 -o kick.h5
run eval-metrics kick.h5 kick.h5 --all-truth --recogniser rec.h5; expect_rc 1
expect_one_error_line eval-metrics; expect_err "the recogniser does not know class 'kick' \(it knows: walk, wave, squat\)"
echo "ok (recogniser: real accuracy $acc_real, FID $fid0 -> $fid1 with training; diversity $div1 / real $div_real; multimodality $mm1 / real $mm_real; accuracy $acc0 -> $acc1)"

# --- other data and bad input: one-line errors, nothing written
synth-actions -q --classes walk --per-class 2 --frames 10 -o short.h5
skel2h5 -q short.h5 -o short-norm.h5  # walks of 10 frames, their own normalization
run classify-actions trained.h5 short-norm.h5  # other lengths and coordinates: converted
expect_rc 0; expect_out "^walk +2 +[0-2] "
skel2h5 -q short.h5 --raw -o short-raw.h5
# --sd-floor: no coordinate's s.d. below it (the root's stay 1); with --raw refused
skel2h5 -q short.h5 --sd-floor 0.2 -o short-floor.h5
h5check -q --kind skeleton short-floor.h5
h5_data short-floor.h5 /normalization/std %.9g | tr -c '0-9.e+-' ' ' |
  awk '{ for (i = 1; i <= NF; i++) if ($i < 0.2 - 1e-9) bad = 1 } END { exit bad }' ||
  fail "an s.d. below --sd-floor 0.2: $(h5_data short-floor.h5 /normalization/std %.3g)"
run skel2h5 short.h5 --sd-floor 0.2 --raw -o x.h5
expect_rc 2; expect_one_error_line skel2h5; expect_err "--sd-floor.*--raw"
run train-actgan "${tiny[@]}" --pretrain-iterations 1 --iterations 1 short-raw.h5 -o raw-model.h5
expect_rc 0; expect_err "not normalized .*training on raw coordinates"
run train-actgan "${tiny[@]}" --iterations 2 untrained.h5 -o bad.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "is a 'actgan-model' file, expected a 'skeleton' file"
bvh() {  # bvh FILE FRAMES: a two-joint arm swinging
  { printf 'HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n'
    printf ' JOINT Arm\n {\n  OFFSET 1 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 1 0 0\n  }\n }\n}\n'
    printf 'MOTION\nFrames: %d\nFrame Time: 0.1\n' "$2"
    for i in $(seq "$2"); do echo "0 0 0 0 0 0 $((i * 10)) 0 0"; done; } > "$1"
}
bvh a.bvh 6 && bvh b.bvh 9
skel2h5 -q --label swing a.bvh b.bvh -o uneven.h5  # whole sequences of 6 and 9 frames
run train-actgan "${tiny[@]}" --iterations 2 uneven.h5 -o bad.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "sequences of 6 and 9 frames: cut equal clips with skel2h5 --length"
[ -f bad.h5 ] && fail "output written after an error"
run gen-actgan trained.h5 --class run -o bad.h5
expect_rc 2; expect_one_error_line gen-actgan; expect_err "unknown class 'run' \(the model knows: walk, wave, squat\)"
run gen-actgan trained.h5 --mix walk:x -o bad.h5
expect_rc 2; expect_err "the weight is not a number"
run gen-actgan trained.h5 --class walk --mix walk:1 -o bad.h5
expect_rc 2; expect_err "--class and --mix exclude each other"
skel2h5 -q --label swing --length 5 a.bvh b.bvh -o arm.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 1 --iterations 1 arm.h5 -o arm-model.h5
run classify-actions arm-model.h5 clips.h5
expect_rc 1; expect_one_error_line classify-actions
expect_err "20 joints x 3: the model was trained on 9 values per pose"
[ -f bad.h5 ] && fail "output written after an error"
echo "ok (errors)"

# --- a validation part: training subjects held out, the log's MMD columns against them
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 10 --validation-subjects 2 --threads 1 clips.h5 -o val1.h5
expect_rc 0
all=$(train-actgan "${tiny[@]}" --pretrain-iterations 0 --iterations 0 clips.h5 -o none.h5 2>&1 | sed -n 's/.*: \([0-9]*\) training clips.*/\1/p')
held=$(sed -n 's/.*validation: \([0-9]*\) clips of subjects 2 held out.*/\1/p' err.txt)
kept=$(sed -n 's/.*: \([0-9]*\) training clips.*/\1/p' err.txt)
[ -n "$held" ] && [ "$held" -gt 0 ] && [ $((kept + held)) = "$all" ] ||
  fail "validation clips: $held held out + $kept trained should be the $all training clips"
expect_err "iteration 20/20: .*; val_mmd_avg [0-9.e-]+; val_mmd_seq [0-9.e-]+; val_mmd_motion_avg [0-9.e-]+; val_mmd_motion_seq [0-9.e-]+\)"
h5check -q --kind actgan-model val1.h5
h5dump -A -d /training/log val1.h5 | grep -q '"iteration loss disc adv smooth cycle gp val_mmd_avg val_mmd_seq val_mmd_motion_avg val_mmd_motion_seq"' ||
  fail "the log's columns should end with val_mmd_avg val_mmd_seq val_mmd_motion_avg val_mmd_motion_seq"
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 10 --validation-subjects 2 --threads 2 clips.h5 -o val2.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 3 --validation-subjects 2 clips.h5 -o val-half.h5
train-actgan -q "${tiny[@]}" --pretrain-iterations 10 --iterations 10 --validation-subjects 2 --resume --checkpoint val-half.h5 \
  clips.h5 -o val-resumed.h5
for obj in /params /training/log /validation/subjects; do
  run h5diff val1.h5 val2.h5 $obj; expect_rc 0
  run h5diff val1.h5 val-resumed.h5 $obj; expect_rc 0
done
run h5diff -q val1.h5 m1.h5 /params; expect_rc 1  # fewer clips, another model
run train-actgan "${tiny[@]}" --pretrain-iterations 10 --iterations 10 --validation-subjects 3 --resume --checkpoint val-half.h5 \
  clips.h5 -o bad.h5
expect_rc 1; expect_one_error_line train-actgan; expect_err "validation-subjects = 2, this run has 3"
run train-actgan "${tiny[@]}" --validation-subjects 9 clips.h5 -o bad.h5
expect_rc 2; expect_one_error_line train-actgan; expect_err "validation subject 9 performs none of the training sequences of clips.h5"
[ -f bad.h5 ] && fail "output written after an error"
echo "ok (validation subjects)"

# --- inspect-actgan: the frame decoder's reach. Poses the decoder itself made (gen-actgan) are
# reached almost exactly by fitted latent codes, far nearer than from h = 0 or by the nearest pose
# of another sequence; real poses get the same table; the baseline has no decoder.
gen-actgan -q --count 4 m1.h5 -o own.h5
inspect-actgan -q m1.h5 own.h5 --all --json own.json > own.txt
grep -q "decoder, fitted codes" own.txt || fail "no table: $(cat own.txt)"
read -r fitted start nearest poses < <(/usr/bin/python3 -c "
import json; j = json.load(open('own.json'))
print(j['decoder']['fitted']['rms'], j['decoder']['start']['rms'], j['nearest_pose']['rms'], j['poses'])")
[ "$poses" = 144 ] || fail "expected 3 classes x 4 sequences x 12 frames, got $poses"
awk -v f="$fitted" -v s="$start" -v n="$nearest" 'BEGIN { exit !(f < 0.05 * s && f < 0.05 * n) }' ||
  fail "the decoder's own poses: fitted RMS $fitted, from h = 0 $start, nearest pose $nearest"
inspect-actgan -q m1.h5 clips.h5 --json real.json > /dev/null
grep -q '"part": "test"' real.json && grep -q '"by_class"' real.json || fail "real poses: $(head -c 300 real.json)"
train-actgan -q "${tiny[@]}" --generator pose --pretrain-iterations 0 --iterations 2 clips.h5 -o pose-only.h5
run inspect-actgan pose-only.h5 clips.h5
expect_rc 1; expect_one_error_line inspect-actgan; expect_err "has no frame decoder"
run inspect-actgan m1.h5 clips.h5 --subjects 77
expect_rc 1; expect_one_error_line inspect-actgan; expect_err "of those subjects"
echo "ok (inspect-actgan: the decoder's own poses at RMS $fitted, from h = 0 $start)"
