# Each pipeline ends with its report page (scripts/report): on the tiny pipeline sets, with real
# tools, OUT/<pipeline>/index.html lists every table, picture and animation the pipeline made,
# each with a caption of its own, a training curve of every model, and the assets a browser
# needs from the file system (three.js, each animation). The page in a real browser: browser.report.
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}" "${DF_PLUGIN_DIR:?}"
export HDF5_PLUGIN_PATH=$DF_PLUGIN_DIR
[ -f /usr/share/javascript/three/three.min.js ] || fail "libjs-three is not installed (scripts/install-deps.sh)"
pipeline() { make -s -C "$DF_SOURCE" -f Makefile.data BIN="$DF_BIN" OUT="$DF_TMP/out" TRAIN_THREADS=1 "$@" > "$DF_TMP/$1.log" 2>&1 ||
               fail "the tiny $1 pipeline failed: $(tail -5 "$DF_TMP/$1.log")"; }
pipeline msae MS_SETS=bumps MS_LEVEL3_SETS= MS_BUMPS="--frames 40 --resolution 8" MS_FIG6_SHAPES=2 \
  bumps_MSAE="--split sequence --validation-fraction 0.2 --iterations 40 --batch 16" \
  bumps_TUNED="--centre-features" bumps_BLOCKS="--kz 3,4"
pipeline bdlstm BD_SETS=finger BD_ABLATION_SETS= finger_TRAIN="--iterations 20 --window 8 --batch 2 --latent 8 --hidden 8 --lstm-layers 1"
pipeline actgan AG_SETS=synthetic AG_SEEDS= AG_PRETRAIN=10 AG_ITERATIONS=10 AG_COUNT=4 AG_OPTIONS="--hidden 16 --fc 32 --batch 8"

for p in msae bdlstm actgan; do
  page=out/$p/index.html
  [ -s "$page" ] || fail "$p: no report page"
  grep -q "report: every table, picture, training curve and animation on one page: $DF_TMP/$page" "$p.log" ||
    fail "$p: the run does not say where its report is"
  n=0
  for f in out/$p/*/*.md out/$p/*/*.png out/$p/*/*.glb; do
    rel=${f#out/$p/}
    grep -qF "<span class=meta>($rel)</span></figcaption>" "$page" || fail "$p: $rel is not on the page"
    n=$((n + 1))
  done
  ! grep -q "no caption registered" "$page" || fail "$p: a picture without its caption: $(grep -o '[^>]*no caption registered[^<]*' "$page" | head -3)"
  for m in out/$p/*/*.h5; do
    case $(h5dump -a /schema -y "$m" 2>/dev/null | sed -n 's/^ *"\(.*\)"$/\1/p') in
      *-model) grep -qF "<span class=meta>(${m#out/$p/})</span></figcaption>" "$page" || fail "$p: no curve of the model $m" ;;
    esac
  done
  [ "$(grep -o '<svg class=curve' "$page" | wc -l)" -ge 2 ] || fail "$p: no training curves drawn"
  for a in three.min.js GLTFLoader.js OrbitControls.js; do [ -s "out/$p/report-assets/$a" ] || fail "$p: report-assets/$a missing"; done
  for g in out/$p/*/*.glb; do
    [ -s "out/$p/report-assets/$(basename "$g").js" ] || fail "$p: the animation $g has no asset"
  done
  echo "ok ($p: $n tables, pictures and animations on the page, each captioned)"
done
