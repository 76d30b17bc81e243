#!/usr/bin/env bash
# Installs the Debian 12 packages deformflow needs to build, test and run its demo.
# Idempotent and fast when everything is present (a dpkg query, no apt-get update).
# Uses sudo when not run as root.
# Usage: scripts/install-deps.sh [--with-bench] [--with-fuzz] [--with-slurm] [--with-blender] [--with-browser] [--with-format]
set -euo pipefail

bench=0
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libopenmesh-dev libhdf5-dev hdf5-tools
  libcli11-dev libfmt-dev libtbb-dev catch2 libzstd-dev nlohmann-json3-dev
  libcairo2-dev fonts-dejavu-core libassimp-dev libtinygltf-dev
  libminizip-dev  # .npz joint arrays (skel2h5); libassimp-dev depends on it too
  libsuitesparse-dev libopenblas0-pthread  # CHOLMOD factors the reconstruction system; OpenBLAS its dense kernels
  assimp-testmodels zstd gnuplot-nox
  libjs-three  # three.js and its glTF loader: the report pages play the animations (scripts/report)
  python3-dev pybind11-dev python3-numpy python3-pytest python3-h5py python3-venv  # the Python module
)
for option in "$@"; do
  case $option in
    --with-bench)  # GNU time (peak memory); the PyTorch timing peer and its allocators
      packages+=(time python3-torch libtcmalloc-minimal4 libjemalloc2)
      bench=1 ;;
    --with-fuzz) packages+=(clang libclang-rt-14-dev) ;;         # libFuzzer + sanitizer runtimes of clang 14
    --with-slurm) packages+=(slurmctld slurmd slurm-client munge) ;;  # the tests' one-node cluster
    --with-blender) packages+=(blender) ;;  # the glTF export opened in Blender (test label blender)
    --with-browser) packages+=(chromium) ;;  # the report page in headless Chromium (test label browser)
    --with-format) packages+=(clang-format) ;;  # make format / format-check (Debian 12: clang-format 14)
    *) echo "install-deps: unknown option $option" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
# The PyTorch peer's BLAS (../shared/peers/torch/README.md): OpenBLAS's OpenMP build unpacked
# beside the system, without switching the system's libblas (Debian's torch would otherwise run
# on the reference BLAS, ~3 GFLOP/s, and every speed-up against it would be inflated).
openblas=/opt/openblas-openmp
need_openblas=0
[[ $bench -eq 1 && ! -f $openblas/usr/lib/x86_64-linux-gnu/openblas-openmp/libblas.so.3 ]] && need_openblas=1
if [[ ${#missing[@]} -eq 0 && $need_openblas -eq 0 ]]; then
  exit 0
fi

sudo=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -q
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "install-deps: installing ${missing[*]}" >&2
  "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
if [[ $need_openblas -eq 1 ]]; then
  echo "install-deps: unpacking libopenblas0-openmp into $openblas (for the PyTorch peer)" >&2
  tmp=$(mktemp -d) && chmod 755 "$tmp"  # apt-get download runs as _apt
  (cd "$tmp" && apt-get download -q libopenblas0-openmp)
  "${sudo[@]}" mkdir -p "$openblas"
  "${sudo[@]}" dpkg -x "$tmp"/libopenblas0-openmp_*.deb "$openblas"
  rm -rf "$tmp"
fi
