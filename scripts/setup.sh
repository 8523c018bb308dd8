#!/usr/bin/env bash
# Installs every Debian 12 package nurbsbench needs (all backends, tests, plots). Idempotent:
# packages already present are not downloaded again, and apt is not touched at all when nothing
# is missing. Run as root (or with sudo available). `--tests` adds what only the tests need (the
# report's browser test: Debian's chromium; the bundle test: patchelf, debootstrap; ccache, which
# lets scripts/test.sh's bundle build reuse its release build's objects), so the main job does not
# download a browser; `--bundle` adds what scripts/bundle.sh needs (patchelf).
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git
  # libraries the core uses
  nlohmann-json3-dev libcli11-dev libfmt-dev libgmp-dev
  # SHA-256 of --plugin libraries for their records
  nettle-dev
  googletest libgtest-dev libgmock-dev libbenchmark-dev
  # fuzzing (scripts/fuzz.sh): clang 14, its libFuzzer/sanitizer runtimes, its OpenMP
  clang libclang-rt-14-dev libomp-14-dev
  # OpenGL strategies: OSMesa, EGL (Mesa llvmpipe), GLU's NURBS tessellator
  libosmesa6-dev libegl-dev libgl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libglu1-mesa-dev
  # Vulkan strategies: loader, lavapipe, glslang, spirv-val, validation layers
  libvulkan-dev mesa-vulkan-drivers glslang-tools glslang-dev spirv-tools vulkan-validationlayers vulkan-tools
  # OpenCL strategies: ICD loader, headers, PoCL
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  # error images and reports
  libopenimageio-dev fonts-dejavu-core python3-matplotlib python3-numpy
  # peers (never the reference)
  libsisl-dev libocct-modeling-data-dev libocct-foundation-dev
  # CAD import (STEP, IGES, BREP) and the real models its tests read
  libocct-data-exchange-dev libocct-modeling-algorithms-dev occt-misc
)

for arg in "$@"; do
  case "$arg" in
    # the report's browser test, the bundle test's minimal Debian root (tests/bundle/), ccache
    --tests) packages+=(chromium patchelf debootstrap ccache) ;;
    # scripts/bundle.sh: the run path of the bundled binary and libraries
    --bundle) packages+=(patchelf) ;;
    *) echo "setup: unknown argument '$arg' (--tests, --bundle)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages already installed"
  exit 0
fi

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
