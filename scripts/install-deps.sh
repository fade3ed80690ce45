#!/usr/bin/env bash
# Installs every Debian package Tissu needs to build, test and render.
# Idempotent: packages already present are skipped. As non-root it prints
# the apt command to run instead of running it.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  libeigen3-dev          # sparse matrices, conjugate gradients
  libhwy-dev             # Google Highway: SIMD kernels, instruction set chosen at run time
  libsuitesparse-dev     # CHOLMOD sparse Cholesky (implicit integrators)
  libopenblas0-serial    # fast single-threaded BLAS under CHOLMOD (same result at any load)
  libglm-dev             # renderer maths
  libassimp-dev          # mesh files (OBJ, PLY, STL, glTF, ...)
  nlohmann-json3-dev     # scene files
  libcgal-dev            # Delaunay triangulation of generated meshes, exact predicates
  libcgal-demo           # sample meshes (a body to dress), extracted by the build
  libgtest-dev           # tests
  libosmesa6-dev         # off-screen OpenGL (Mesa llvmpipe)
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev  # MP4/H.264
  libstb-dev             # stb_truetype, stb_image_write
  libpng-dev             # PNG reader
  libisal-dev            # ISA-L igzip: fast deflate for the PNG writer
  fonts-dejavu-core      # caption font
  ffmpeg                 # ffprobe, used by tests to check videos decode
  clang libclang-rt-14-dev  # libFuzzer and sanitizers for scripts/fuzz.sh
  slurm-wlm munge        # the one-node cluster of the slurm batch test (scripts/slurm-test-cluster.sh)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages; run as root:" >&2
  echo "  apt-get update && $cmd" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
$cmd
