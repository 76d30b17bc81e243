#!/usr/bin/env bash
# Unpacks ../shared/data archives into the build tree once (ctest fixture of shared-data tests).
set -euo pipefail
src=$1 dst=$2
mkdir -p "$dst"
for archive in "$src"/meshseq/*.tar.zst "$src"/skeleton/*.tar.zst; do
  [ -f "$archive" ] || continue
  name=$(basename "$archive" .tar.zst)
  stamp="$dst/.$name.unpacked"
  if [ ! -f "$stamp" ] || [ "$archive" -nt "$stamp" ]; then
    rm -rf "${dst:?}/$name.tmp" && mkdir -p "$dst/$name.tmp"
    tar --zstd -xf "$archive" -C "$dst/$name.tmp"
    rm -rf "${dst:?}/$name" && mv "$dst/$name.tmp" "$dst/$name"
    touch "$stamp"
  fi
done
