#!/usr/bin/env bash
# Installs the Debian 12 packages deformflow needs to build, test and run its demo.
# Idempotent and fast when everything is present (a dpkg query, no apt-get update).
# Uses sudo when not run as root. Usage: scripts/install-deps.sh [--with-bench] [--with-fuzz] [--with-slurm]
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libopenmesh-dev libhdf5-dev hdf5-tools
  libcli11-dev libfmt-dev libtbb-dev catch2 libzstd-dev nlohmann-json3-dev
  libcairo2-dev fonts-dejavu-core libassimp-dev
  assimp-testmodels zstd gnuplot-nox
)
for option in "$@"; do
  case $option in
    --with-bench) packages+=(time python3-torch libjemalloc2) ;;  # GNU time (peak memory); the PyTorch timing peer
    --with-fuzz) packages+=(clang libclang-rt-14-dev) ;;         # libFuzzer + sanitizer runtimes of clang 14
    --with-slurm) packages+=(slurmctld slurmd slurm-client munge) ;;  # the tests' one-node cluster
    *) echo "install-deps: unknown option $option" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
"${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
