# The demo's report page in a real browser (label browser; skipped, exit 77, where Debian's
# chromium is not installed): headless Chromium opens out/demo/index.html from the file system
# (as a user does), and the test fails on a console error, a missing picture or script, an
# animation that did not load, draw or move; two screenshots of the first animation at two moments
# must differ (the mesh moved). The screenshots are kept under $DF_ARTIFACTS.
# The page is the one cli.pipeline's demo run made (ctest fixture demo_report).
set -euo pipefail
: "${DF_TMP:?}" "${DF_ARTIFACTS:?}" "${DF_DEMO:?the demo output directory}"
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chromium" ] || { echo "chromium is not installed: skipped (apt-get install chromium)"; exit 77; }
fail() { echo "FAIL: $*" >&2; exit 1; }
page=$DF_DEMO/index.html
[ -f "$page" ] || fail "no report page $page (cli.pipeline makes it)"
rm -rf "$DF_TMP"; mkdir -p "$DF_TMP" "$DF_ARTIFACTS"
# A closed machine: no network, no GPU (SwiftShader's WebGL), a fresh profile per run.
browse() {
  timeout 120 "$chromium" --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader --use-angle=swiftshader \
    --disable-quic --no-first-run --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$(mktemp -d -p "$DF_TMP")" --enable-logging=stderr --v=0 "$@"
}

# The page's own account after 8 s: every picture loaded, every animation loaded, drawn and moving,
# no script error (window errors, unhandled rejections and console.error are collected there).
browse --virtual-time-budget=8000 --window-size=1200,4000 --dump-dom "file://$page" > "$DF_TMP/dom.html" 2> "$DF_TMP/console.txt" ||
  fail "chromium failed: $(tail -5 "$DF_TMP/console.txt")"
status=$(sed -n 's/.*<div id="status" class="\([a-z]*\)">\([^<]*\)<.*/\1: \2/p' "$DF_TMP/dom.html")
echo "status: $status"
[ -n "$status" ] || fail "the page has no status line: its scripts did not run"
[[ $status == "ok: animations:"* ]] || fail "the page reports: $status"
n=$(grep -o 'animations: [0-9]* of [0-9]*' <<<"$status" | awk '{ print $4 }')
[ "${n:-0}" -ge 1 ] || fail "no animation on the page"
grep -q "animations: $n of $n loaded, $n drawn, $n moving" <<<"$status" ||
  fail "not every animation loaded, drew and moved: $status"
# What the browser itself logged: uncaught errors and files it could not load.
if grep -E "Uncaught|ERR_FILE_NOT_FOUND|Failed to load resource|Not allowed to load local resource" "$DF_TMP/console.txt"; then
  fail "the browser reported errors (above)"
fi
for img in $(grep -o '<img src="[^"]*"' "$DF_TMP/dom.html" | sed 's/<img src="//; s/"$//'); do
  [ -s "$DF_DEMO/$img" ] || fail "the page shows a missing picture $img"
done
echo "ok (page: $n animations loaded, drawn and moving; no console error; every picture present)"

# Two moments of the first animation, alone on the page (index.html#only-anim-0: nothing else on
# it changes, so two screenshots differ only where the mesh is).
shot() { browse --virtual-time-budget="$1" --window-size=700,480 --screenshot="$2" "file://$page#only-anim-0" 2>/dev/null ||
           fail "no screenshot at $1 ms"; }
shot 1500 "$DF_ARTIFACTS/report-anim-early.png"
shot 5000 "$DF_ARTIFACTS/report-anim-late.png"
[ "$(head -c 4 "$DF_ARTIFACTS/report-anim-early.png" | tail -c 3)" = PNG ] || fail "the screenshot is not a PNG"
cmp -s "$DF_ARTIFACTS/report-anim-early.png" "$DF_ARTIFACTS/report-anim-late.png" &&
  fail "the first animation looks the same at 1.5 s and at 5 s"
echo "ok (two moments differ; screenshots in $DF_ARTIFACTS)"
