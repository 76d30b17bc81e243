# Killing a tool mid-write leaves no output and no temporary (SIGTERM, SIGINT); after SIGKILL
# the final name is still absent, so "file exists => complete" holds for Make.
source "$(dirname "$0")/lib.sh"

# Starts a long synth-meshseq writing $1, waits until its temporary exists, sends signal $2,
# and checks the exit status 128+signal.
kill_mid_write() {
  local output=$1 sig=$2 pid i
  shift 2
  synth-meshseq -q --frames 4000 "$@" -o "$output" &
  pid=$!
  for i in $(seq 1 500); do
    [ -n "$(find . -maxdepth 1 -name ".$(basename "$output").tmp-*" | head -1)" ] && break
    sleep 0.01
  done
  [ -n "$(find . -maxdepth 1 -name ".$(basename "$output").tmp-*" | head -1)" ] || fail "no temporary appeared"
  sleep 0.2
  kill -s "$sig" "$pid"
  set +e; wait "$pid"; local status=$?; set -e
  echo "$sig -> exit $status"
  [ -e "$output" ] && fail "$output exists after $sig"
  [ "$sig" = KILL ] && return 0
  [ "$status" -gt 128 ] || fail "expected death by signal, exit $status"
  expect_no_temporaries .
}

kill_mid_write term.h5 TERM --resolution 48
kill_mid_write int.h5 INT --resolution 48
kill_mid_write frames TERM --kind flag --resolution 30   # a directory output
kill_mid_write killed.h5 KILL --resolution 48
echo "ok"
