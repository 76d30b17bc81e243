# The demo pipeline runs from Makefile.data, validates, and is up to date afterwards (no rule
# re-runs when its inputs are unchanged).
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}"
# (a short MSAE run: the demo's 1,000 iterations take about 2 minutes)
run make -C "$DF_SOURCE" -f Makefile.data demo BIN="$DF_BIN" OUT="$DF_TMP/out" DEMO_MSAE_ITERATIONS=40
expect_rc 0
expect_out "faerie.h5: OK, acap"
expect_out "finger \(400 deg twist\): max [0-9.e-]+ x bbox diagonal"
expect_out "faerie \(MD2, 16 animations\): max"
[ -f out/demo/flag/0000.obj ] || fail "flag frames missing"
[ "$(ls out/demo/faerie-meshes | wc -l)" = 198 ] || fail "faerie meshes missing"
h5check -q out/demo/finger.h5 out/demo/bumps.h5 out/demo/finger-acap.h5
expect_out "level 0: [0-9]+ kept, [0-9]+ dropped"
expect_out "coarse +0 "
# the printed numbers, each read from the tools' --json and labelled as what it is
expect_out "^     BD-LSTM: +[0-9.e-]+  \([0-9.e-]+ x [0-9.e-]+\)$"
expect_out "^     E_rms x 1000 \(unit ball\) [0-9.e-]+; relative squared error of the features: max [0-9.e-]+, mean [0-9.e-]+$"
expect_out "^     MMD_avg [0-9.e-]+, MMD_seq [0-9.e-]+; of motion \(frame differences\): MMD_avg [0-9.e-]+, MMD_seq [0-9.e-]+$"
accuracy=$(printf '%.3f / %.3f' $(collect-metrics --values --columns overall out/demo/actgan-accuracy.json) \
  $(collect-metrics --values --columns overall out/demo/actgan-accuracy-generated.json))
expect_out "^     $accuracy$"
mmd=$(collect-metrics --values --columns mmd_avg out/demo/actgan-mmd.json)
grep -qE "^     MMD_avg $(printf '%.4g' "$mmd")," out.txt || fail "the printed MMD_avg is not the JSON's $mmd"
# No pipeline reads a number out of a tool's human-readable table (pipelines read --json).
table_text='position error|E_rms \*|STED \*spatial|relative squared error \*max|frame pairs|spread of samples|error per sample|\^all |\^level |\^\$\(2\) \*|"mmd_|"pairwise_ratio'
if grep -nE "(sed|awk|grep).*($table_text)" "$DF_SOURCE"/pipelines/*.mk; then
  fail "a pipeline parses a human-readable table (above)"
fi
# the report page: every picture and animation of the demo on it; the last lines say where it is
for f in out/demo/*.png out/demo/*.glb; do
  grep -qF "<span class=meta>($(basename "$f"))</span></figcaption>" out/demo/index.html ||
    fail "the demo's report lacks $(basename "$f")"
done
grep -vE "^make(\[[0-9]+\])?: .* directory" out.txt | tail -n 2 > last.txt  # (make -C's own lines aside)
[ "$(head -n 1 last.txt)" = "== everything above on one page, the animations playing: $DF_TMP/out/demo/index.html" ] &&
  tail -n 1 last.txt | grep -q "open it with: xdg-open $DF_TMP/out/demo/index.html" ||
  fail "the demo does not end saying where its report is: $(cat last.txt)"
h5check -q --kind msae-model out/demo/msae-model.h5
h5check -q --kind components out/demo/msae-kept.h5
[ -s out/demo/msae-components.png ] || fail "no MSAE picture"
run make -C "$DF_SOURCE" -q -f Makefile.data "$DF_TMP/out/demo/faerie-meshes/stand01.obj" \
  "$DF_TMP/out/demo/finger-meshes/finger-0000.obj" "$DF_TMP/out/demo/bumps.h5" BIN="$DF_BIN" OUT="$DF_TMP/out"
expect_rc 0
echo "ok"

# A pipeline unpacks a data archive once: a fresh copy of DATA (new time, same bytes) re-runs
# nothing, other bytes unpack again. unpack_once DIR NAME SRC: DATA/DIR/NAME.tar.zst, whose one
# top directory is NAME, unpacks into out/SRC.
unpack_once() {
  local archive=data/$1/$2.tar.zst unpacked=$DF_TMP/out/$3/.unpacked before
  unpack() { make -s -C "$DF_SOURCE" -f Makefile.data "$unpacked" BIN="$DF_BIN" OUT="$DF_TMP/out" DATA="$DF_TMP/data" ||
               fail "unpacking $archive failed"; }
  mkdir -p "data/$1" "pack/$2"
  echo "v 0 0 0" >"pack/$2/a.obj"
  tar --zstd -cf "$archive" -C pack "$2"
  unpack
  [ -f "out/$3/$2/a.obj" ] || fail "$archive not unpacked"
  before=$(stat -c %y "$unpacked")
  touch -d '+1 min' "$archive"
  unpack
  [ "$(stat -c %y "$unpacked")" = "$before" ] || fail "$archive with a new time but the same bytes was unpacked again"
  echo "v 1 0 0" >"pack/$2/b.obj"
  tar --zstd -cf "$archive" -C pack "$2"
  touch -d '+2 min' "$archive"
  unpack
  [ -f "out/$3/$2/b.obj" ] || fail "a changed $archive was not unpacked again"
}
unpack_once meshseq tiny bdlstm/tiny/src                  # the BD-LSTM pipeline's (and MSAE's) mesh sequences
unpack_once skeleton UTKinect actgan/utkinect/src         # the ActGAN pipeline's skeletons
echo "ok (unpack once)"

# A model retrains when its options (the set's, an ablation's) change, and only then (a stand-in
# train-bdlstm counts the runs).
mkdir -p fakebin
ln -s "$DF_BIN/collect-metrics" fakebin/  # the pipelines read numbers from JSON with it
cat >fakebin/train-bdlstm <<'SH'
#!/bin/sh
for a; do [ "${prev:-}" = -o ] && out=$a; prev=$a; done
echo run >>"$DF_TMP/train-runs"; touch "$out"
SH
chmod +x fakebin/train-bdlstm
touch out/bdlstm/tiny/data.h5
train() { make -s -C "$DF_SOURCE" -f Makefile.data "$DF_TMP/out/bdlstm/tiny/${2:-model}.h5" BIN="$DF_TMP/fakebin" \
            OUT="$DF_TMP/out" DATA="$DF_TMP/data" tiny_TRAIN="$1" ${3:+no-kl_FLAGS="$3"} >/dev/null ||
            fail "training rule failed"; }
runs() { wc -l <train-runs; }
train "--iterations 5"
train "--iterations 5"
[ "$(runs)" = 1 ] || fail "unchanged options retrained the model ($(runs) runs)"
train "--iterations 6"
[ "$(runs)" = 2 ] || fail "new options did not retrain the model ($(runs) runs)"
train "--iterations 6" model-no-kl
train "--iterations 6" model-no-kl
[ "$(runs)" = 3 ] || fail "an ablation model was not trained once ($(runs) runs in all)"
train "--iterations 6" model-no-kl "--no-kl --seed 2"
[ "$(runs)" = 4 ] || fail "new ablation flags did not retrain the ablation model ($(runs) runs in all)"
echo "ok (retrain on new options)"

# Validation candidates: windowN trains the paper's form on N-frame windows with the set's other
# options, a named candidate keeps its own window, an unknown name is refused before anything runs.
cat >fakebin/train-bdlstm <<'SH'
#!/bin/sh
for a; do [ "${prev:-}" = -o ] && out=$a; prev=$a; done
echo "$*" >"$out.argv"; touch "$out"
SH
validate() { make -s -C "$DF_SOURCE" -f Makefile.data "$DF_TMP/out/bdlstm/tiny/validate/$1.h5" BIN="$DF_TMP/fakebin" \
               OUT="$DF_TMP/out" DATA="$DF_TMP/data" tiny_OPTIONS="--batch 2 --stride 3" BD_CANDIDATES="$2"; }
validate window48 "paper window48" >/dev/null 2>&1 || fail "the window48 candidate did not train"
grep -q -- "--window 48 --batch 2 --stride 3 --validation-fraction" out/bdlstm/tiny/validate/window48.h5.argv &&
  grep -q -- "--l2-scope all --l2-weight 1 --decoder-init zero" out/bdlstm/tiny/validate/window48.h5.argv ||
  fail "window48 did not train the paper's form on 48-frame windows: $(cat out/bdlstm/tiny/validate/window48.h5.argv)"
validate paper "paper window48" >/dev/null 2>&1 || fail "the paper candidate did not train"
grep -q -- "--window 32 --batch 2 --stride 3 " out/bdlstm/tiny/validate/paper.h5.argv ||
  fail "the paper candidate lost its 32-frame window: $(cat out/bdlstm/tiny/validate/paper.h5.argv)"
msg=$(validate bogus "paper bogus" 2>&1) && fail "an unknown candidate was accepted"
echo "$msg" | grep -q "no candidate 'bogus'" || fail "unknown candidate: unclear message: $msg"
[ ! -e out/bdlstm/tiny/validate/bogus.h5 ] || fail "an unknown candidate trained"
validate no-kl-w48 "paper no-kl-w48" >/dev/null 2>&1 || fail "the no-kl-w48 candidate did not train"
grep -qE -- "--window 48 --batch 2 --stride 3 --validation-fraction [0-9.]+ --no-kl " out/bdlstm/tiny/validate/no-kl-w48.h5.argv ||
  fail "no-kl-w48 did not train no-kl on 48-frame windows: $(cat out/bdlstm/tiny/validate/no-kl-w48.h5.argv)"
echo "ok (validation candidates)"

# A set's remedies chosen on validation (S_CHOSEN) go to its model only: Table 2's variants,
# the paper's form among them, train without them.
make -s -C "$DF_SOURCE" -f Makefile.data "$DF_TMP/out/bdlstm/tiny/model.h5" "$DF_TMP/out/bdlstm/tiny/model-paper.h5" \
  "$DF_TMP/out/bdlstm/tiny/model-no-l2.h5" BIN="$DF_TMP/fakebin" OUT="$DF_TMP/out" DATA="$DF_TMP/data" \
  tiny_TRAIN="--iterations 7" tiny_CHOSEN="--no-kl" >/dev/null || fail "training rules with chosen remedies failed"
grep -q -- "--iterations 7 --no-kl /" out/bdlstm/tiny/model.h5.argv ||
  fail "the set's model lost its chosen remedies: $(cat out/bdlstm/tiny/model.h5.argv)"
grep -q -- "--iterations 7 --paper-form /" out/bdlstm/tiny/model-paper.h5.argv &&
  grep -q -- "--iterations 7 --paper-form --no-l2 /" out/bdlstm/tiny/model-no-l2.h5.argv ||
  fail "a Table 2 variant got the chosen remedies: $(cat out/bdlstm/tiny/model-paper.h5.argv out/bdlstm/tiny/model-no-l2.h5.argv)"
variants() { make -s -C "$DF_SOURCE" -f Makefile.data OUT="$DF_TMP/out" DATA="$DF_TMP/data" BD_ABLATION_SETS=tiny "$@" \
               --eval 'print-variants: ; @echo $(call fig2_variants,tiny)' print-variants; }
[ "$(variants tiny_CHOSEN=--paper-form)" = "unidirectional standard no-kl no-l2" ] ||
  fail "when the paper's form is the set's model it is not a variant too: '$(variants tiny_CHOSEN=--paper-form)'"
[ "$(variants)" = "paper unidirectional standard no-kl no-l2" ] ||
  fail "with train-bdlstm's defaults (the remedies) Table 2 needs the paper's form: '$(variants)'"
[ "$(variants tiny_CHOSEN=--no-kl)" = "paper unidirectional standard no-kl no-l2" ] ||
  fail "with chosen remedies Table 2 needs the paper's form: '$(variants tiny_CHOSEN=--no-kl)'"
echo "ok (chosen remedies)"

# Candidates over the held-out placements (issue 67), with the real tools on a small finger: each
# placement trains with its own --test-part and seed (the set's own --test-part dropped), the
# table gives each placement's mean error as the JSON has it (a set's own list of placements where
# it has one), the better baseline's ratio is 1,
# and the summary's worst is the set's ratio; an unknown placement is refused before anything runs.
mkdir -p out/bdlstm/place
synth-meshseq -q --kind finger --frames 200 --resolution 4 -o place-frames.h5
obj2acap -q place-frames.h5 -o out/bdlstm/place/data.h5
placements() { make -s -C "$DF_SOURCE" -f Makefile.data "$@" BIN="$DF_BIN" OUT="$DF_TMP/out" DATA="$DF_TMP/data" \
                 BD_PLACEMENT_SETS=place place_WINDOW=8 place_OPTIONS="--batch 2 --test-part random" \
                 place_PLACEMENT_ITERATIONS=3 BD_PLACEMENT_CANDIDATES="stopping paper" TRAIN_THREADS=1; }
placements BD_PLACEMENTS="end start random2" place_PLACEMENTS="end random2" place_NO_ROOM=random2 bdlstm-placements >placements.txt 2>&1 ||
  fail "bdlstm-placements failed: $(tail -n 5 placements.txt)"
# a set's own list of placements (pcow leaves random3 out: no room for its window there)
grep -q "^| method | end | random2 | mean over placements" out/bdlstm/place/placements.md &&
  [ ! -e out/bdlstm/place/place/start ] || fail "the set's own placements were not the ones trained: $(ls out/bdlstm/place/place)"
# a placement without room for the fastest speed and a stopping part trains as the defaults yield there
grep -q -- "--speeds 0,0.5,1 --stopping-fraction 0$" out/bdlstm/place/place/random2/stopping.args &&
  grep -q -- "--speeds 0,0.5,1,1.5 --stopping-fraction 0.1 --stopping-every 25$" out/bdlstm/place/place/end/stopping.args ||
  fail "a placement without room kept the candidate's speeds or stopping part: $(cat out/bdlstm/place/place/*/stopping.args)"
grep -q -- "--window 8 --batch 2 --validation-fraction 0.1 --test-part random --seed 2 " out/bdlstm/place/place/random2/stopping.args &&
  grep -q -- "--test-part end --seed 1 " out/bdlstm/place/place/end/paper.args ||
  fail "a placement trained with other parts: $(cat out/bdlstm/place/place/*/*.args)"
for m in stopping paper damped-extrapolation-0.8 zero-motion linear-extrapolation; do
  grep -qE "^\| $m \| [0-9.]+ \| [0-9.]+ \| [0-9.]+ / [0-9.]+ / [0-9.]+ \([0-9.]+\) \| [0-9.]+ \| [0-9.]+ \|$" out/bdlstm/place/placements.md ||
    fail "placements.md lacks the $m row: $(cat out/bdlstm/place/placements.md)"
done
zero_end=$(printf '%.1f' "$(collect-metrics --values --columns vertex_error.mean_relative \
  out/bdlstm/place/place/end/stopping.vstatic.veval.json | awk '{ print 1000 * $1 }')")
grep -qE "^\| zero-motion \| $zero_end \|" out/bdlstm/place/placements.md ||
  fail "zero motion's end cell is not its JSON's $zero_end: $(grep zero-motion out/bdlstm/place/placements.md)"
grep -E "^\| (zero-motion|linear-extrapolation) \|" out/bdlstm/place/placements.md | grep -q "| 1.000 |$" ||
  fail "neither baseline is the better one (ratio 1): $(cat out/bdlstm/place/placements.md)"
ratio=$(awk -F'|' '$2 == " stopping " { gsub(/ /, "", $(NF - 1)); print $(NF - 1) }' out/bdlstm/place/placements.md)
# the reference row is no candidate of the summary
grep -q "damped" out/bdlstm/placements.md && fail "the damped reference is a candidate of the summary: $(cat out/bdlstm/placements.md)"
grep -qE "^\| stopping \| $ratio \| $ratio \|$" out/bdlstm/placements.md ||
  fail "the summary's worst is not the set's ratio $ratio: $(cat out/bdlstm/placements.md)"
msg=$(placements BD_PLACEMENTS="end side" bdlstm-placements 2>&1) && fail "an unknown placement was accepted"
echo "$msg" | grep -q "no placement 'side'" || fail "unknown placement: unclear message: $msg"
echo "ok (candidates over the placements)"

# ActGAN at other training seeds: each seed trains ours and the baseline with the set's options
# and --seed N; seeds.md sets the two side by side and counts where ours is lower.
cat >fakebin/train-actgan <<'SH'
#!/bin/sh
for a; do [ "${prev:-}" = -o ] && out=$a; prev=$a; done
echo "$*" >"$out.argv"; touch "$out"
SH
chmod +x fakebin/train-actgan
mkdir -p out/actgan/tiny
touch out/actgan/tiny/data.h5
agmake() { make -s -C "$DF_SOURCE" -f Makefile.data BIN="$DF_TMP/fakebin" OUT="$DF_TMP/out" DATA="$DF_TMP/data" \
             AG_SEEDS=2 "$@" >/dev/null || fail "ActGAN seed rules failed: $*"; }
# every set trains at train-actgan's iteration count unless AG_ITERATIONS says otherwise
mkdir -p out/actgan/tiny2 && touch out/actgan/tiny2/data.h5
agmake "$DF_TMP/out/actgan/tiny2/model-seed2.h5"
! grep -q -- "--iterations" out/actgan/tiny2/model-seed2.h5.argv ||
  fail "the default count was overridden: $(cat out/actgan/tiny2/model-seed2.h5.argv)"
agmake AG_ITERATIONS=7 "$DF_TMP/out/actgan/tiny/model-seed2.h5" "$DF_TMP/out/actgan/tiny/model-pose-seed2.h5"
grep -qE -- "--pretrain-iterations 1000 --iterations 7 .*--seed 2 " out/actgan/tiny/model-seed2.h5.argv ||
  fail "seed 2's model: $(cat out/actgan/tiny/model-seed2.h5.argv)"
grep -qE -- "--pretrain-iterations 0 --iterations 7 .*--generator pose --seed 2 " out/actgan/tiny/model-pose-seed2.h5.argv ||
  fail "seed 2's baseline: $(cat out/actgan/tiny/model-pose-seed2.h5.argv)"
mmd_json() { printf '{\n  "mmd_avg": %s,\n  "mmd_seq": %s,\n  "mmd_motion_avg": %s,\n  "mmd_motion_seq": %s,\n  "classes": {}\n}\n' "$2" "$3" "$4" "$5" >"$1"; }
mmd_json out/actgan/tiny/gen.mmd.json 0.1 0.3 0.5 0.7                 # ours, seed 1
mmd_json out/actgan/tiny/gen-pose.mmd.json 0.2 0.2 0.6 0.8            # the baseline, seed 1
mmd_json out/actgan/tiny/gen-seed2.mmd.json 0.3 0.1 0.5 0.9         # ours, seed 2
mmd_json out/actgan/tiny/gen-pose-seed2.mmd.json 0.4 0.2 0.5 0.8    # the baseline, seed 2 (a tie: not lower)
j=out/actgan/tiny; J=$DF_TMP/$j
agmake -o $J/gen.mmd.json -o $J/gen-pose.mmd.json -o $J/gen-seed2.mmd.json -o $J/gen-pose-seed2.mmd.json $J/seeds.md
grep -qF "| 2 | 0.3000 | 0.1000 | 0.5000 | 0.9000 | 0.4000 | 0.2000 | 0.5000 | 0.8000 |" $j/seeds.md &&
  grep -qF "| motion MMD_avg | 0.5000 (0.5000 - 0.5000) | 0.5500 (0.5000 - 0.6000) | 1 of 2 seeds |" $j/seeds.md &&
  grep -qF "| MMD_avg | 0.2000 (0.1000 - 0.3000) | 0.3000 (0.2000 - 0.4000) | 2 of 2 seeds |" $j/seeds.md &&
  grep -qF "| MMD_seq | 0.2000 (0.1000 - 0.3000) | 0.2000 (0.2000 - 0.2000) | 1 of 2 seeds |" $j/seeds.md &&
  grep -qF "| motion MMD_seq | 0.8000 (0.7000 - 0.9000) | 0.8000 (0.8000 - 0.8000) | 1 of 2 seeds |" $j/seeds.md ||
  fail "seeds.md: $(cat $j/seeds.md)"
echo "ok (ActGAN seeds)"

# A set's options for separate training (<set>_SEPARATE) go to its separately trained variants only.
msargs() { make -s -C "$DF_SOURCE" -f Makefile.data OUT="$DF_TMP/out" tiny_MSAE="--iterations 9" tiny_SEPARATE="--separate-rate continue" \
             --eval "print-args: ; @echo '\$(call ms_args,tiny,$1)'" print-args; }
for v in separate separate-noatt; do
  [ "$(msargs $v)" = "--iterations 9 $(make -s -C "$DF_SOURCE" -f Makefile.data --eval "p: ; @echo '\$(${v}_FLAGS)'" p) --separate-rate continue" ] ||
    fail "variant $v lacks the set's separate-training options: $(msargs $v)"
done
for v in "" noatt tan; do
  case "$(msargs "$v")" in *separate-rate*) fail "variant '$v' got the separate-training options: $(msargs "$v")" ;; esac
done
echo "ok (MSAE's separate-training options per set)"

# MSAE's Table 2 adds the Table 4 strategy whose model ends with the lowest validation E_rms
# (the last loss line of its log), and its test E_rms is that strategy's Table 4 cell; without
# validation shapes there is no such row. (Real tools, tiny bumps, 40 iterations per model.)
mstables() { make -s -C "$DF_SOURCE" -f Makefile.data BIN="$DF_BIN" OUT="$DF_TMP/$1" MS_SETS=bumps MS_LEVEL3_SETS= \
               MS_BUMPS="--frames 40 --resolution 8" bumps_MSAE="--split sequence $2 --iterations 40 --batch 16" \
               bumps_TUNED="--centre-features" bumps_BLOCKS="--kz 3,4" TRAIN_THREADS=1 "$DF_TMP/$1/msae/bumps/table2.md" "$DF_TMP/$1/msae/bumps/table4.md" >/dev/null 2>&1 ||
               fail "MSAE tables ($2) were not made"; }
mstables ms-val "--validation-fraction 0.2"
m=ms-val/msae/bumps
best=$(for v in msae:joint,with msae-noatt:joint,without msae-separate:separate,with msae-separate-noatt:separate,without; do
         sed -n 's/.*validation_erms \([0-9.]*\).*/\1/p' "$m/${v%%:*}.log" | tail -n 1 | sed "s/\$/ ${v#*:}/"
       done | sort -g | head -n 1)
[ -n "$best" ] || fail "the MSAE logs have no validation E_rms"
row=$(grep "validation shapes choose" $m/table2.md) || fail "Table 2 has no row for the strategy chosen on validation: $(cat $m/table2.md)"
strategy=${best#* }; training=${strategy%,*}; attention=${strategy#*,}
echo "$row" | grep -q "($training training $attention attention: validation E_rms " ||
  fail "Table 2 chose another strategy than the lowest validation E_rms ($best): $row"
cell=$(grep "^| $training |" $m/table4.md | awk -F'|' -v c=$([ "$attention" = with ] && echo 3 || echo 4) '{ print $c }' | cut -d/ -f1 | tr -d ' ')
[ "$(echo "$row" | awk -F'|' '{ print $4 }' | tr -d ' ')" = "$cell" ] ||
  fail "the chosen strategy's E_rms is not its Table 4 cell ($cell): $row"
# the tool's defaults are Table 2's MSAE rows; the set's own settings a row of their own (their K_z)
grep -q "^| MSAE, the tool's defaults (2 levels, attention, joint), encoder's codes (the paper's protocol) | 10 + 10 x 50 |" $m/table2.md &&
  grep -q "^| MSAE, the set's own settings .* | 3 + 3 x 4 |" $m/table2.md || fail "Table 2's MSAE rows: $(cat $m/table2.md)"
grep -q -- "--iterations 40 --batch 16 --paper-form --centre-features --kz 3,4" $m/msae-tuned.args &&
  ! grep -q -- "--paper-form\|--kz" $m/msae.args || fail "the models' arguments: $(cat $m/msae.args $m/msae-tuned.args)"
# the yardstick of issue 65, SPLOCS's algorithm on ACAP features, is a row read from its own fit
acap=$(collect-metrics --values --columns erms "$m/recon-splocs-acap.eval" | awk '{ printf "%.3f", $1 }')
grep -q "^| SPLOCS's algorithm on ACAP features | 60 | $acap |" $m/table2.md ||
  fail "Table 2 has no SPLOCS-on-ACAP row of its fit ($acap): $(cat $m/table2.md)"
mstables ms-noval ""
! grep -q "validation shapes choose" ms-noval/msae/bumps/table2.md || fail "a chosen row without validation shapes"
echo "ok (MSAE's Table 2: the strategy chosen on validation, $training training $attention attention)"

# Each synthetic set is made with its own arguments and its localization is measured against its
# own planted regions: bumps12 with one fine region has 3, the tiny bumps above 6. (bumps12 in a
# form that keeps a level-1 component in 40 iterations on this tiny surface, for the sheets below.)
mssynth() { make -s -C "$DF_SOURCE" -f Makefile.data BIN="$DF_BIN" OUT="$DF_TMP/ms-val" MS_SETS=$1 MS_LEVEL3_SETS= \
              MS_BUMPS="--frames 40 --resolution 8" bumps_MSAE="--split sequence --validation-fraction 0.2 --iterations 40 --batch 16" \
              MS_BUMPS12="--frames 40 --resolution 8 --fine-regions 1" bumps12_MSAE="--split sequence --iterations 40 --batch 16 --paper-form --kz 10,50 --support proximal" \
              bumps_TUNED= bumps12_TUNED= MS_TUNED_SETS= TRAIN_THREADS=1 "$DF_TMP/ms-val/msae/$1/$2" >/dev/null 2>&1 || fail "$1's $2 was not made"; }
regions() { grep -cE '^ +[0-9]' "$1"; }
mssynth bumps12 localization.md
[ "$(regions ms-val/msae/bumps12/localization.md)" = 6 ] && [ "$(head -n 1 ms-val/msae/bumps12/localization.md | cut -d' ' -f1)" = bumps12 ] ||
  fail "bumps12's localization is not of its own 3 regions (kept and before pruning): $(cat ms-val/msae/bumps12/localization.md)"
mssynth bumps localization.md
[ "$(regions ms-val/msae/bumps/localization.md)" = 12 ] || fail "bumps' localization is not of its 6 regions: $(cat ms-val/msae/bumps/localization.md)"
echo "ok (MSAE's synthetic sets: each with its own arguments and planted regions)"

# The kept components are drawn one sheet per level; a level with none kept has no sheet.
mssynth bumps12 components.png
m=ms-val/msae/bumps12
for level in 0 1; do
  kept=$(sed -n "s/^level $level: \([0-9]*\) kept.*/\1/p" $m/pruning.txt)
  sheet=$m/components.png; [ $level = 0 ] || sheet=$m/components-L1.png
  if [ "${kept:-0}" -gt 0 ]; then
    [ "$(head -c 4 "$sheet" | tail -c 3)" = PNG ] || fail "level $level keeps $kept components but has no sheet $sheet"
  else
    [ ! -e "$sheet" ] || fail "level $level keeps none but has a sheet $sheet"
  fi
done
grep -q "^level 1: [1-9]" $m/pruning.txt || fail "the tiny bumps12 keeps no level-1 component, so the level-1 sheet is not checked: $(cat $m/pruning.txt)"
echo "ok (MSAE's components drawn one sheet per level)"
