#!/usr/bin/env bash
# Golden-file runner: runs one case of tests/golden/<tool>/<case>/ with the real binaries and
# compares what it wrote with the stored expected files (see tests/golden/README.md).
#
#   run.sh CASE_DIR            compare; exit 1 with the first differences
#   run.sh --update CASE_DIR   (re)write CASE_DIR/expected from this run
#
# Environment: DF_BIN (the tools), DF_TEST_BIN (golden_compare and the test drivers, e.g.
# h5_mutate, on PATH for setups), DF_TMP (work directory root).
set -uo pipefail
update=0
if [ "${1:-}" = --update ]; then update=1; shift; fi
[ $# = 1 ] || { echo "usage: run.sh [--update] CASE_DIR" >&2; exit 2; }
: "${DF_BIN:?DF_BIN must point at the built tools}" "${DF_TEST_BIN:?}" "${DF_TMP:?}"
here=$(cd "$(dirname "$0")" && pwd)
case_dir=$(cd "$1" && pwd) || exit 2
name="$(basename "$(dirname "$case_dir")")/$(basename "$case_dir")"
[ -f "$case_dir/cmd" ] || { echo "$name: no cmd file" >&2; exit 2; }
work="$DF_TMP/$name"
rm -rf "$work" && mkdir -p "$work/run" || exit 2
export PATH="$DF_BIN:$DF_TEST_BIN:$PATH" SOURCE_DATE_EPOCH=0 LC_ALL=C
cd "$work/run"

# 1. inputs: shipped files, then the recorded commands that make the others
[ -d "$case_dir/inputs" ] && cp -r "$case_dir/inputs/." .
if [ -f "$case_dir/setup" ]; then
  if ! bash -e "$case_dir/setup" >"$work/setup.log" 2>&1; then
    echo "FAIL $name: setup failed:"; sed 's/^/  /' "$work/setup.log"; exit 1
  fi
fi
find . -type f | sort >"$work/inputs.list"

# 2. the command under test
bash -e "$case_dir/cmd" >"$work/stdout" 2>"$work/stderr"
rc=$?
# outputs named in the case's `ignore` file (globs; e.g. a large model file whose effect the
# command prints) are neither stored nor compared
find . -type f | sort | comm -13 "$work/inputs.list" - | sed 's|^\./||' | while read -r f; do
  keep=1
  if [ -f "$case_dir/ignore" ]; then
    while read -r glob _; do case $glob in ''|'#'*) continue ;; esac; [[ $f == $glob ]] && keep=0; done <"$case_dir/ignore"
  fi
  [ $keep = 1 ] && echo "$f"
done >"$work/outputs.list"

# 3a. --update: the expected files are this run's outputs, stdout, exit status and (for a
#     failing command) stderr
if [ $update = 1 ]; then
  rm -rf "$case_dir/expected" && mkdir -p "$case_dir/expected"
  while read -r f; do mkdir -p "$case_dir/expected/$(dirname "$f")" && cp "$f" "$case_dir/expected/$f"; done <"$work/outputs.list"
  cp "$work/stdout" "$case_dir/expected/@stdout"
  if [ $rc != 0 ]; then echo $rc >"$case_dir/expected/@rc"; cp "$work/stderr" "$case_dir/expected/@stderr"; fi
  echo "updated $name: $(wc -l <"$work/outputs.list") output file(s), exit $rc"
  exit 0
fi

# 3b. compare: exit status, the set of files, then each file within its tolerance
expected="$case_dir/expected"
[ -d "$expected" ] || { echo "FAIL $name: no expected/ (make golden-update CASE=$name)"; exit 1; }
problems=()
want_rc=0
[ -f "$expected/@rc" ] && want_rc=$(cat "$expected/@rc")
if [ "$rc" != "$want_rc" ]; then
  problems+=("exit status $rc, expected $want_rc; stderr: $(head -c 600 "$work/stderr")")
fi
(cd "$expected" && find . -type f ! -name '@*' | sed 's|^\./||' | sort) >"$work/expected.list"
for f in $(comm -23 "$work/expected.list" "$work/outputs.list"); do problems+=("$f: not written"); done
for f in $(comm -13 "$work/expected.list" "$work/outputs.list"); do problems+=("$f: written, but not expected"); done
# the case's tolerances first, then the defaults of every case
cat "$case_dir/tolerances" "$here/tolerances" 2>/dev/null >"$work/tolerances"
compare() {  # compare NAME GOT EXPECTED
  local args=(--name "$1" --tolerances "$work/tolerances")
  "$DF_TEST_BIN/golden_compare" -q "${args[@]}" "$2" "$3" >"$work/compare.txt" 2>&1 ||
    problems+=("$(cat "$work/compare.txt")")
}
for f in $(comm -12 "$work/expected.list" "$work/outputs.list"); do compare "$f" "$f" "$expected/$f"; done
compare @stdout "$work/stdout" "$expected/@stdout"
[ -f "$expected/@stderr" ] && compare @stderr "$work/stderr" "$expected/@stderr"

if [ ${#problems[@]} = 0 ]; then
  echo "ok $name ($(wc -l <"$work/expected.list") file(s) and stdout match)"
  exit 0
fi
echo "FAIL $name (command: $(grep -v '^#' "$case_dir/cmd" | head -3 | tr '\n' ' '))"
printf '%s\n' "${problems[@]}" | head -40
echo "(work directory: $work; if the change is intended: make golden-update CASE=$name)"
exit 1
