# Helpers for CLI tests: each test script sources this, works in a fresh $DF_TMP, and fails
# with a message naming what differed.
set -euo pipefail
: "${DF_BIN:?DF_BIN must point at the built tools}" "${DF_TMP:?}"
rm -rf "$DF_TMP"
mkdir -p "$DF_TMP"
cd "$DF_TMP"
export PATH="$DF_BIN:$PATH"

fail() { echo "FAIL: $*" >&2; exit 1; }
# run CMD...: runs a command, keeping its exit status in $rc and its output in out.txt/err.txt
run() { set +e; "$@" >out.txt 2>err.txt; rc=$?; set -e; }
expect_rc() { [ "$rc" = "$1" ] || fail "expected exit $1, got $rc from: $(cat err.txt)"; }
expect_err() { grep -qE -- "$1" err.txt || fail "stderr does not match /$1/: $(cat err.txt)"; }
expect_out() { grep -qE -- "$1" out.txt || fail "stdout does not match /$1/: $(head -c 2000 out.txt)"; }
# The error is exactly one line "TOOL: error: ..." (nothing else on stderr).
expect_one_error_line() {
  [ "$(grep -c . err.txt)" = 1 ] || fail "expected one stderr line, got: $(cat err.txt)"
  grep -qE "^$1: error: " err.txt || fail "expected '$1: error: ...', got: $(cat err.txt)"
}
# h5_data FILE DATASET [FORMAT]: the dataset's values as h5dump prints them, its DATA block only
h5_data() { h5dump -d "$2" -y -w 0 ${3:+-m "$3"} "$1" | sed -n '/^   DATA {/,/^   }/p'; }
# No temporaries (.NAME.tmp-*) left in a directory.
expect_no_temporaries() {
  local left
  left=$(find "${1:-.}" -maxdepth 1 -name '.*.tmp-*' | head -5)
  [ -z "$left" ] || fail "temporaries left behind: $left"
}
# wait_for FILE REGEX [SECONDS]: until FILE has a line matching REGEX (at most SECONDS, 20 unless said)
wait_for() {
  for _ in $(seq 1 $(( ${3:-20} * 100 ))); do grep -qE -- "$2" "$1" 2>/dev/null && return 0; sleep 0.01; done
  fail "no line /$2/ in $1: $(cat "$1")"
}
# expect_close NAME GOT WANT RTOL: |GOT - WANT| <= RTOL * max(|WANT|, 1e-12)
expect_close() {
  awk -v n="$1" -v g="$2" -v w="$3" -v t="$4" 'BEGIN {
    d = g - w; if (d < 0) d = -d; s = w < 0 ? -w : w; if (s < 1e-12) s = 1e-12;
    if (d > t * s) { printf "FAIL: %s = %s, expected %s (relative tolerance %s)\n", n, g, w, t > "/dev/stderr"; exit 1 } }' ||
    exit 1
}
