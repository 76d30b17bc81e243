#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time: first every seed/regression input of its corpus
# once, then fuzzing from them into a scratch corpus. Exit 0 = no crash; on a crash libFuzzer
# writes the input as crash-* in the work directory and this prints how to keep it.
#   run.sh TARGET CORPUS_DIR WORK_DIR SECONDS
set -euo pipefail
target=$1 corpus=$2 work=$3 seconds=$4
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work/new" "$work/tmp"
cd "$work"
export TMPDIR=$work/tmp ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$here/../lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# HDF5 filter plugins installed on the machine (Debian's hdf5-filter-plugin, hdf5-plugin-lzf, ...)
# are not ours to fuzz, and some leak in their initialisers when HDF5 loads them: an empty plugin
# path keeps them out (the targets register our zstd filter in-process).
mkdir -p "$work/no-plugins" && export HDF5_PLUGIN_PATH=$work/no-plugins
# 1. the corpus as regression inputs (each must pass)
if ! "$target" -runs=0 "$corpus" >regression.log 2>&1; then
  tail -n 60 regression.log
  echo "FAIL: $(basename "$target") fails on an input of its corpus $corpus"
  exit 1
fi
# 2. fuzzing: 2 GiB RSS limit, 10 s per input at most
if ! "$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
      new "$corpus" >fuzz.log 2>&1; then
  tail -n 60 fuzz.log
  echo "FAIL: $(basename "$target") crashed; the input is $(ls "$work"/crash-* "$work"/oom-* "$work"/timeout-* 2>/dev/null | head -1)." \
       "Fix the cause, then copy it into $corpus/ as a regression input."
  exit 1
fi
grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+.*DONE" fuzz.log || true
echo "ok: $(basename "$target") ran ${seconds} s without a crash ($(ls new | wc -l) new corpus inputs)"
