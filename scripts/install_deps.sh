#!/usr/bin/env bash
# Installs the Debian packages DEMLink needs to build, test and benchmark.
# Idempotent: only missing packages are installed; safe to run again.
# Usage: scripts/install_deps.sh [--with-peers]   (--with-peers adds LIGGGHTS for bench/)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libasio-dev libprotobuf-dev protobuf-compiler
  # scripts/build_pic_protobuf.sh: `apt-get source protobuf` unpacks with dpkg-source (the
  # system's apt sources need a deb-src entry for bookworm)
  dpkg-dev
  libeigen3-dev libspdlog-dev libfmt-dev
  # FEM bodies: CHOLMOD's supernodal Cholesky for large meshes (optional: without it the
  # build falls back to Eigen's SimplicialLDLT)
  libsuitesparse-dev
  # every program's command line (server/cli/): header-only CLI11
  libcli11-dev
  # the LIGGGHTS backend (optional: built only when both are found; docs/scale-out.md)
  libliggghts-dev libopenmpi-dev openmpi-bin
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-protobuf
  # scripts/plot_cosim.py (PNG plots, headless Agg backend)
  python3-matplotlib
  # scripts/check_modelica.py: the Modelica grammar (scripts/modelica/modelica.lark) runs on Lark
  python3-lark
  # tests/core/deformable/data: regenerating the Gmsh test meshes (not needed to build or test)
  gmsh
  # tests/multihost: network namespaces and veth pairs (ip netns, ip link)
  iproute2
  # the view (docs/view.md): three.js for the page, served from /usr/share/javascript/three;
  # headless Chromium and Node for its browser test (tests/view/check_view_in_browser.mjs)
  libjs-three chromium nodejs
  # scripts/run_fuzz.sh: clang with the libFuzzer/ASan runtimes (only recommended by clang,
  # and recommendations are not installed below).
  clang libclang-rt-14-dev
  # the win64 client side (scripts/build_win64.sh, tests/windows): mingw-w64 with POSIX
  # threads, objdump for the import check, wine64 alone runs 64-bit programs (no i386
  # architecture needed), dpkg-dev unpacks protobuf's source package (scripts/win64_protobuf.sh)
  g++-mingw-w64-x86-64-posix binutils-mingw-w64-x86-64 wine64 dpkg-dev
)
if [[ "${1:-}" == "--with-peers" ]]; then
  packages+=(liggghts time)
fi

# `apt-get source` for the protobuf runtimes built from Debian's source (scripts/win64_protobuf.sh,
# scripts/build_pic_protobuf.sh).
"$(dirname "$0")/lib/ensure_deb_src.sh"

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
