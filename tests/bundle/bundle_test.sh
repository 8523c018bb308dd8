#!/usr/bin/env bash
# The relocatable bundle in an environment as bare as a GPU node's (issue 27): a minimal Debian
# root made by debootstrap that holds glibc, Mesa's drivers (llvmpipe for EGL, lavapipe for
# Vulkan) and PoCL's OpenCL driver, with the GPU API loaders deleted from it, so that only the
# bundle's own loaders can serve, and none of nurbsbench's build dependencies. In it:
#   - every ELF file of the bundle resolves each library it needs inside the bundle or to glibc;
#   - `nurbsbench list` finds a device on each API through the bundle's loaders and names the
#     driver file that served it;
#   - `gpu-check --tiny` runs to completion: results sets with ok records, a report, an archive.
#
#   tests/bundle/bundle_test.sh [--no-build]    root: build/bundle-root (kept between runs)
# Needs root (chroot, mounts) and Debian's package mirror (debootstrap, the first time).
set -euo pipefail
cd "$(dirname "$0")/../.."
repo=$PWD
fail() { echo "bundle_test: FAILED: $*" >&2; exit 1; }

[ "${1:-}" = --no-build ] || bash scripts/bundle.sh --no-setup
bundle_tar=$(ls dist/nurbsbench-*-linux-x86_64.tar.gz | head -n1)
[ -f "$bundle_tar" ] || fail "no bundle in dist/ (scripts/bundle.sh)"
bundle_dir=${bundle_tar%.tar.gz}
bytes=$(du -sb "$bundle_dir" | cut -f1)
[ "$bytes" -le $((48 * 1024 * 1024)) ] || fail "$bundle_dir is $bytes bytes (limit 48 MiB)"

source scripts/glibc_sonames.sh
# 1. Every ELF file needs only what the bundle holds, or glibc.
elf_files=0
while IFS= read -r f; do
  head -c 4 "$f" | grep -q $'\x7fELF' || continue
  elf_files=$((elf_files + 1))
  while read -r needed; do
    is_glibc "$needed" && continue
    [ -f "$bundle_dir/lib/$needed" ] || fail "$f needs $needed, which is neither in lib/ nor glibc's"
  done < <(readelf -d "$f" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
done < <(find "$bundle_dir" -type f)
rpath=$(readelf -d "$bundle_dir/bin/nurbsbench" | sed -n 's/.*(RPATH).*\[\(.*\)\]/\1/p')
[ "$rpath" = '$ORIGIN/../lib' ] || fail "bin/nurbsbench's RPATH is '$rpath', not \$ORIGIN/../lib"
echo "bundle_test: $elf_files ELF files resolve inside the bundle or to glibc; RPATH $rpath"

# 2. The minimal root: glibc, coreutils and the drivers; no loaders, no build dependencies.
root=$repo/build/bundle-root
drivers=(libegl-mesa0 libgl1-mesa-dri mesa-vulkan-drivers pocl-opencl-icd)
if [ ! -f "$root/.complete" ]; then
  rm -rf "$root"
  # The machine's own Debian mirror (from its apt sources), never a host written here.
  mirror=$(sed -n 's/^URIs:[[:space:]]*\([^[:space:]]*\).*/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null |
    grep -v security | head -n1)
  [ -n "$mirror" ] || mirror=$(awk '$1 == "deb" {print $2; exit}' /etc/apt/sources.list 2>/dev/null)
  [ -n "$mirror" ] || fail "no Debian mirror in /etc/apt/sources.list(.d)"
  echo "bundle_test: debootstrap bookworm (minbase + ${drivers[*]}) into $root"
  debootstrap --variant=minbase --include="$(IFS=,; echo "${drivers[*]}")" bookworm "$root" "$mirror" \
    >"$repo/build/bundle-root.log" 2>&1 || { tail -n 20 "$repo/build/bundle-root.log" >&2; fail "debootstrap"; }
  touch "$root/.complete"
fi
# The GPU API loaders the drivers pulled in go: only the bundle's may serve.
for loader in libvulkan.so.1 libEGL.so.1 libGLdispatch.so.0 libOpenCL.so.1 libGLX.so.0 libOpenGL.so.0 libGL.so.1; do
  find "$root/usr/lib" "$root/lib" -name "$loader*" -exec rm -f {} + 2>/dev/null || true
done
# (Python comes with PoCL's clang; it is no dependency of the bundle.)
for absent in usr/include/fmt usr/include/vulkan usr/include/CL usr/include/EGL usr/include/nlohmann \
              usr/bin/cmake usr/bin/g++ usr/lib/x86_64-linux-gnu/libfmt.so.9 \
              usr/lib/x86_64-linux-gnu/libTKernel.so.7 usr/lib/x86_64-linux-gnu/libtbb.so.12; do
  [ ! -e "$root/$absent" ] || fail "the minimal root holds /$absent: it is not as bare as a GPU node"
done
rm -rf "$root/opt/bundle" "$root/tmp/gpu-check"
mkdir -p "$root/opt/bundle"
tar xzf "$bundle_tar" -C "$root/opt/bundle"
inner=/opt/bundle/$(basename "$bundle_dir")

# 3. In the root: list, a small run, gpu-check --tiny. A private mount namespace holds /proc and
# /dev and /sys (the isolated measurements re-execute /proc/self/exe; PoCL reads the CPU topology
# from /sys), gone when it ends.
in_root() {
  unshare --mount --fork bash -c "mount --make-rprivate / &&
    mount -t proc proc '$root/proc' && mount --rbind /dev '$root/dev' && mount --rbind /sys '$root/sys' &&
    chroot '$root' /usr/bin/env -i PATH=/usr/bin:/bin HOME=/tmp /bin/bash -c \"\$0\"" "$1"
}
in_root "ldd $inner/bin/nurbsbench" >"$repo/build/bundle-ldd.txt" || fail "ldd in the root"
if grep -q "not found" "$repo/build/bundle-ldd.txt"; then
  cat "$repo/build/bundle-ldd.txt" >&2
  fail "a library is not found in the root"
fi
while read -r soname path; do
  is_glibc "$soname" && continue
  path=${path/\/bin\/..\/lib\//\/lib\/}  # $ORIGIN/../lib as ldd prints it
  [[ "$path" == "$inner/lib/"* ]] || fail "$soname resolves to $path in the root, outside the bundle"
done < <(awk '$2 == "=>" {print $1, $3}' "$repo/build/bundle-ldd.txt")

in_root "$inner/bin/nurbsbench list" >"$repo/build/bundle-list.txt" 2>&1 || { cat "$repo/build/bundle-list.txt" >&2; fail "list in the root"; }
for api in "Vulkan" "OpenGL (EGL)" "OpenCL"; do
  section=$(sed -n "/^  $api:/,/^  [A-Z]/p" "$repo/build/bundle-list.txt")
  grep -q "<- used without --device" <<<"$section" || { cat "$repo/build/bundle-list.txt" >&2; fail "$api: no device in the root"; }
  grep -q ", loaded: " <<<"$section" || { cat "$repo/build/bundle-list.txt" >&2; fail "$api: no driver file named as loaded"; }
  grep -q "a CPU figure" <<<"$section" || fail "$api: the software device is not labelled a CPU figure"
done
echo "bundle_test: list in the root finds a device on Vulkan, EGL and OpenCL through the bundle's loaders"

in_root "$inner/bin/gpu-check /tmp/gpu-check --tiny --minutes 4" >"$repo/build/bundle-gpu-check.txt" 2>&1 ||
  { cat "$repo/build/bundle-gpu-check.txt" >&2; fail "gpu-check --tiny in the root"; }
archive=$(ls "$root"/tmp/gpu-check/nurbsbench-gpu-check-*.tar.gz 2>/dev/null | head -n1)
[ -f "$archive" ] || fail "gpu-check wrote no archive"
[ "$(stat -c %s "$archive")" -le $((16 * 1024 * 1024)) ] || fail "$archive is over 16 MiB"
tar tzf "$archive" >"$repo/build/bundle-archive.txt"
grep -q "^report/REPORT.md$" "$repo/build/bundle-archive.txt" || fail "the archive holds no report"
grep -q "skipped\|cut " "$root/tmp/gpu-check/SUMMARY.txt" && { cat "$root/tmp/gpu-check/SUMMARY.txt" >&2; fail "gpu-check --tiny dropped steps within 4 minutes"; }
for set in fig7-time-vs-points fig8-many-surfaces fig14-deboor-vs-basis deforming fig8-trimmed-ducks \
           fig9-tspline-time-vs-points rpns-mapping-uniform fig7-large; do
  results=$root/tmp/gpu-check/sets/$set/results.json
  [ -f "$results" ] || fail "gpu-check wrote no $set set"
  for strategy in vk-ksquad gl-pingpong cl-stair cpu-tensor; do
    [ "$set" = rpns-mapping-uniform ] && [ "$strategy" != vk-ksquad ] && continue
    [ "$set" = fig9-tspline-time-vs-points ] && continue
    grep -q "\"strategy\": \"$strategy\"" "$results" || fail "$set has no $strategy record"
  done
  grep -q '"status": "ok"' "$results" || fail "$set has no ok record"
done
echo "bundle_test: gpu-check --tiny in the root: $(grep -c . "$root/tmp/gpu-check/SUMMARY.txt") summary lines, archive $(basename "$archive") ($(($(stat -c %s "$archive") / 1024)) KiB)"
