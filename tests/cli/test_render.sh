# render-mesh end to end: a sheet of an acap file, generated frames (positions reconstructed from
# features) coloured by their error against the truth with the truth row, mesh directories, one
# PNG per frame, thread independence (identical bytes), and bad inputs (one error line, no PNG).
source "$(dirname "$0")/lib.sh"

# png_size FILE: "WIDTH HEIGHT" from the PNG header (IHDR).
png_size() {
  [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$1 is not a PNG"
  od -An -tu1 -j16 -N8 "$1" | awk '{ printf "%d %d\n", $1*16777216 + $2*65536 + $3*256 + $4, $5*16777216 + $6*65536 + $7*256 + $8 }'
}

synth-meshseq -q --frames 40 --resolution 4 --periods 2 -o finger.h5
obj2acap -q finger.h5 -o data.h5

# --- a sheet: 1 row x 4 columns of 100-pixel panels (+ captions and margins)
render-mesh -q data.h5 --every 10 --size 100 --view side -o sheet.png
read -r w h < <(png_size sheet.png)
[ "$w" -ge 400 ] && [ "$w" -lt 600 ] && [ "$h" -ge 100 ] && [ "$h" -lt 200 ] || fail "sheet.png is $w x $h"
render-mesh -q data.h5 --frames 0,5,10-12 --size 100 -o five.png
read -r w5 _ < <(png_size five.png)
[ "$w5" -ge 500 ] || fail "5 frames should give 5 columns, got width $w5"

# --- colour by a dataset given by name: a per-vertex [V] weight added with h5import
V=$(h5check data.h5 | sed -n 's/^ *V = \([0-9]*\).*/\1/p')
cp data.h5 weighted.h5
awk -v n="$V" 'BEGIN { for (i = 0; i < n; i++) print i / n }' > w.txt
printf 'PATH /extra/weight\nINPUT-CLASS TEXTFP\nRANK 1\nDIMENSION-SIZES %d\nOUTPUT-CLASS FP\nOUTPUT-SIZE 64\n' "$V" > w.cfg
h5import w.txt -c w.cfg -o weighted.h5
render-mesh weighted.h5 --frames 0,20 --color /extra/weight --size 80 -o weight.png 2>weight.log
grep -qE "colour 0 \.\. 0\.9[0-9]* /extra/weight" weight.log || fail "dataset colouring: $(cat weight.log)"
render-mesh -q weighted.h5 --frames 0,20 --size 80 -o plain.png
cmp -s weight.png plain.png && fail "--color /extra/weight did not change the picture"

# --- generated frames (no positions: reconstructed), error colouring, truth row, thread independence
train-bdlstm -q --window 8 --batch 2 --latent 8 --hidden 8 --lstm-layers 1 --iterations 10 --print-every 10 \
  --seed 3 data.h5 -o m.h5
gen-bdlstm -q m.h5 data.h5 --test-every 2 --initial 2 --length 4 -o pred.h5
gen-bdlstm -q m.h5 data.h5 --test-every 2 --initial 2 --length 4 --method linear -o lin.h5
fig=(pred.h5 lin.h5 --error-vs data.h5 --show-truth --sequence 0 --steps 2,4 --size 80 --row-labels "truth,BD-LSTM,linear")
render-mesh "${fig[@]}" --threads 1 -o fig1.png 2>fig.log
grep -q "3 rows x 2 frames, colour 0 .. " fig.log || fail "unexpected summary: $(cat fig.log)"
render-mesh -q "${fig[@]}" --threads 2 -o fig2.png
cmp -s fig1.png fig2.png || fail "--threads 1 and 2 gave different PNG bytes"
render-mesh -q "${fig[@]}" --threads 2 -f -o fig2.png
cmp -s fig1.png fig2.png || fail "a second run gave different PNG bytes"
render-mesh -q "${fig[@]}" --fit first -o fitfirst.png
cmp -s fig1.png fitfirst.png && fail "--fit first drew the same picture as --fit all"
render-mesh -q "${fig[@]}" --colormap jet --range 0,0.5 -o jet.png
cmp -s fig1.png jet.png && fail "--colormap jet --range did not change the picture"

# --- mesh directories and one PNG per frame
acap2obj -q data.h5 --frames 0-5 -o meshes
render-mesh -q meshes --size 64 -o 'frames/{index:02d}-{frame}.png'
[ "$(ls frames | wc -l)" = 6 ] || fail "expected 6 PNG files: $(ls frames)"
[ -f frames/05-5.png ] || fail "pattern names: $(ls frames)"
read -r wf hf < <(png_size frames/03-3.png)
[ "$wf" -lt 200 ] && [ "$hf" -lt 200 ] || fail "a per-frame PNG is one panel, got $wf x $hf"
expect_no_temporaries frames

# --- bad inputs: one error line, no PNG, no temporaries
bad() {  # bad RC PATTERN ARGS...: render-mesh ARGS -o bad.png fails with RC and PATTERN
  local want=$1 pattern=$2; shift 2
  rm -f bad.png
  run render-mesh "$@" -o bad.png
  expect_rc "$want"; expect_one_error_line render-mesh; expect_err "$pattern"
  [ ! -e bad.png ] || fail "a PNG was written although render-mesh failed: $*"
  expect_no_temporaries .
}
bad 2 "no frames selected" pred.h5 --steps 99
bad 2 "outside 0-39" data.h5 --frames 5,40
bad 2 "needs generated frames" data.h5 --steps 1
synth-meshseq -q --frames 80 --resolution 6 --periods 2 -o other.h5
bad 1 "error reference has [0-9]+ vertices" data.h5 --error-vs other.h5
: > empty.obj
bad 1 "empty.obj" empty.obj
bad 2 "error-vs" data.h5 --color error
bad 1 "no dataset /extra/none" weighted.h5 --color /extra/none
synth-meshseq -q --kind bumps --frames 3 --resolution 6 -o bumps.h5
bad 1 "shape \[V\] or \[N, V\]" bumps.h5 --color /synthetic/regions
bad 2 "no sequence 'walk'" data.h5 --sequence walk
bad 2 "at most 64" other.h5 --size 16
bad 2 "bad --view" data.h5 --view diagonal
bad 2 "--fit must be all or first" data.h5 --fit some
bad 1 "model" m.h5
run render-mesh data.h5 -o out.jpg
expect_rc 2; expect_one_error_line render-mesh; expect_err "png"
run render-mesh data.h5 --every 10 -o sheet.png
expect_rc 1; expect_one_error_line render-mesh; expect_err "exists"
echo "render-mesh CLI: all checks passed"
