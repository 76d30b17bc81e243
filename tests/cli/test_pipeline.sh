# The demo pipeline runs from Makefile.data, validates, and is up to date afterwards (no rule
# re-runs when its inputs are unchanged).
source "$(dirname "$0")/lib.sh"
: "${DF_SOURCE:?}"
run make -C "$DF_SOURCE" -f Makefile.data demo BIN="$DF_BIN" OUT="$DF_TMP/out"
expect_rc 0
expect_out "finger.h5: OK, acap"
expect_out "bumps.h5: OK, acap"
[ -f out/demo/flag/0000.obj ] || fail "flag frames missing"
run make -C "$DF_SOURCE" -q -f Makefile.data "$DF_TMP/out/demo/finger.h5" "$DF_TMP/out/demo/bumps.h5" BIN="$DF_BIN" OUT="$DF_TMP/out"
expect_rc 0
echo "ok"
