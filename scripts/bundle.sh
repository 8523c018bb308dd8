#!/usr/bin/env bash
# The relocatable bundle, for a GPU machine that has a driver and nothing else (no packages, no
# root, no network): dist/nurbsbench-<version>-linux-x86_64/ and a .tar.gz beside it.
#
#   bin/nurbsbench   the `bundle` preset's build: every GPU-API strategy (EGL, Vulkan, OpenCL) and
#                    the CPU strategies; no OSMesa/LLVM, CAD import or image files. Its run path is
#                    $ORIGIN/../lib, as DT_RPATH so that it also holds for the libraries a loader
#                    opens (a DT_RUNPATH would not be searched for them).
#   bin/gpu-check    scripts/gpu_check.sh: devices, the canonical sets at GPU sizes, the report.
#   share/nurbsbench/gates.json   the CI accuracy gates, which gpu-check checks every set against.
#   lib/             every shared library bin/nurbsbench needs but glibc's, the GPU API loaders
#                    among them (libvulkan, glvnd's libEGL and libGLdispatch, ocl-icd's libOpenCL);
#                    the vendor drivers (ICDs) are the machine's, found at run time.
#
# Runs on any x86-64 Linux whose glibc is at least the build machine's (Debian 12: 2.36).
#   scripts/bundle.sh              # set up, build, bundle
#   scripts/bundle.sh --no-setup   # the packages are installed: build and bundle only
set -euo pipefail
cd "$(dirname "$0")/.."
max_bytes=$((48 * 1024 * 1024))

[ "${1:-}" = --no-setup ] || bash scripts/setup.sh --bundle
cmake --preset bundle >/dev/null
cmake --build --preset bundle -j "$(nproc)" --target nurbsbench

version=$(sed -n 's/^project(nurbsbench VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
name="nurbsbench-$version-linux-x86_64"
dist="dist/$name"
rm -rf "$dist" "dist/$name.tar.gz"
mkdir -p "$dist/bin" "$dist/lib"
install -m 755 build/bundle/harness/nurbsbench "$dist/bin/nurbsbench"
install -m 755 scripts/gpu_check.sh "$dist/bin/gpu-check"
install -D -m 644 results/gates.json "$dist/share/nurbsbench/gates.json"

# glibc's libraries stay the machine's (they must match its ld.so); everything else travels.
source scripts/glibc_sonames.sh
while read -r soname path; do
  is_glibc "$soname" && continue
  [ -f "$path" ] || { echo "bundle: $soname not found ($path)" >&2; exit 1; }
  cp -L "$path" "$dist/lib/$soname"
done < <(ldd "$dist/bin/nurbsbench" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}')

strip --strip-unneeded "$dist/bin/nurbsbench" "$dist"/lib/*.so*
patchelf --force-rpath --set-rpath '$ORIGIN/../lib' "$dist/bin/nurbsbench"
for lib in "$dist"/lib/*.so*; do
  patchelf --force-rpath --set-rpath '$ORIGIN' "$lib"
done

cat >"$dist/README.txt" <<EOF
nurbsbench $version (commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)), relocatable
bundle for x86-64 Linux with glibc >= $(ldd --version | head -n1 | awk '{print $NF}').

  bin/gpu-check OUTDIR [--minutes N] [--driver-dir DIR]   the one-call GPU check
  bin/nurbsbench list                                     devices and drivers per API
  bin/nurbsbench run --out DIR                            the default benchmark

The GPU APIs' loaders are in lib/; the drivers are this machine's: Vulkan ICD manifests, glvnd EGL
vendor files and OpenCL .icd files in their standard folders, or where VK_DRIVER_FILES /
VK_ICD_FILENAMES / VK_ADD_DRIVER_FILES, __EGL_VENDOR_LIBRARY_FILENAMES / __EGL_VENDOR_LIBRARY_DIRS
and OCL_ICD_VENDORS point, or in a folder given with --driver-dir DIR. A figure measured on
llvmpipe, lavapipe or PoCL is a CPU figure and is labelled so.
EOF

tar czf "dist/$name.tar.gz" -C dist "$name"
bytes=$(du -sb "$dist" | cut -f1)
packed=$(stat -c %s "dist/$name.tar.gz")
echo "bundle: $dist ($((bytes / 1024 / 1024)) MiB, $(ls "$dist/lib" | wc -l) libraries), dist/$name.tar.gz ($((packed / 1024 / 1024)) MiB)"
if [ "$bytes" -gt "$max_bytes" ]; then
  echo "bundle: $dist is $bytes bytes, over the 48 MiB limit" >&2
  du -b "$dist"/lib/* | sort -n | tail -n 5 >&2
  exit 1
fi
