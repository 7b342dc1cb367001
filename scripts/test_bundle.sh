#!/usr/bin/env bash
# Tests the GPU bundle (scripts/gpu_bundle.sh, docs/gpu.md) where nothing of chcrt's build is installed: a minimal
# Debian root (debootstrap --variant=minbase bookworm) with only Mesa's EGL runtime added (libegl-mesa0,
# libgl1-mesa-dri for llvmpipe; no glvnd libEGL, no dev packages, no OpenImageIO, no Embree, no OSMesa) and
# python3 (which the GPU machine has, for gpu_check.sh). The bundle is unpacked there and run under chroot:
#   ldd of the bundled binary (everything resolves, nothing from the root but glibc), run.sh info, render (PNG and
#   EXR, from another working directory), verify (GLSL vs Embree, CHC+RT vs pure BVH), a small bench, the one-line
#   error of --gl osmesa without OSMesa, and gpu_check.sh --quick (skip it with CHCRT_TEST_BUNDLE_GPU_CHECK=0).
# Every command and its output go to OUT/test_bundle.log; the last line says PASS or FAIL.
# Usage: scripts/test_bundle.sh [TARBALL] [OUT]   (default: builds one with scripts/gpu_bundle.sh; OUT
#        out/test_bundle). Needs root (chroot, mount) and, the first time, the Debian mirror (debootstrap,
#        apt-get); the root is kept in CHCRT_BUNDLE_ROOT (default /var/tmp/chcrt-bundle-root) for later runs.
#        Not part of ctest or .ci/run for these reasons.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $(id -u) -ne 0 ]]; then
  echo "test_bundle: needs root (debootstrap, chroot, mount)" >&2
  exit 2
fi
tarball=${1:-}
out=${2:-out/test_bundle}
root=${CHCRT_BUNDLE_ROOT:-/var/tmp/chcrt-bundle-root}
mirror=${CHCRT_DEBIAN_MIRROR:-http://deb.debian.org/debian}
packages=(libegl-mesa0 libgl1-mesa-dri python3)
mkdir -p "$out"
out=$(cd "$out" && pwd -P)
log=$out/test_bundle.log
: >"$log"
say() { echo "test_bundle: $*" | tee -a "$log" >&2; }

if [[ -z $tarball ]]; then
  say "building the bundle (scripts/gpu_bundle.sh $out)"
  tarball=$(scripts/gpu_bundle.sh "$out" | tail -n 1)
fi
[[ -f $tarball ]] || { say "no bundle at $tarball"; exit 2; }
tarball=$(cd "$(dirname "$tarball")" && pwd -P)/$(basename "$tarball")

# 1. The minimal root (made once; the marker lists what was added to minbase).
marker=$root/.chcrt-bundle-root
if [[ ! -f $marker || $(cat "$marker") != "${packages[*]}" ]]; then
  command -v debootstrap >/dev/null || { apt-get update -qq && apt-get install -y -qq debootstrap >/dev/null; }
  rm -rf "$root.new"
  say "debootstrap --variant=minbase bookworm $root ($mirror)"
  debootstrap --variant=minbase bookworm "$root.new" "$mirror" >>"$log" 2>&1
  say "adding ${packages[*]} (--no-install-recommends)"
  chroot "$root.new" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${packages[@]}" >>"$log" 2>&1
  chroot "$root.new" apt-get clean
  echo "${packages[*]}" >"$root.new/.chcrt-bundle-root"
  rm -rf "$root"
  mv "$root.new" "$root"
fi

mounted=()
cleanup() {
  local i
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount "${mounted[i]}" 2>/dev/null || umount -l "${mounted[i]}" || true; done
}
trap cleanup EXIT
for fs in proc sys dev; do
  if ! mountpoint -q "$root/$fs"; then
    mount --bind "/$fs" "$root/$fs"
    mounted+=("$root/$fs")
  fi
done

# 2. The bundle, unpacked into the root.
rm -rf "$root/opt/bundle" "$root/tmp/work"
mkdir -p "$root/opt/bundle" "$root/tmp/work"
tar -C "$root/opt/bundle" -xzf "$tarball"
name=$(ls "$root/opt/bundle")
b=/opt/bundle/$name
say "bundle $(basename "$tarball") ($(stat -c %s "$tarball") bytes) unpacked in $root$b"

failures=0
# check NAME EXPECTED_EXIT COMMAND: runs COMMAND in the root (working directory /tmp/work), logs it and its output
# (LAST_OUTPUT), counts a failure; CHECK_OK is 1 when the exit code was the expected one.
check() {
  local name=$1 expected=$2
  shift 2
  local output rc=0
  {
    echo
    echo "### $name"
    echo "\$ chroot $root sh -c 'cd /tmp/work && $*'"
  } >>"$log"
  output=$(chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root bash -c "cd /tmp/work && $*" 2>&1) || rc=$?
  echo "$output" >>"$log"
  echo "(exit $rc)" >>"$log"
  LAST_OUTPUT=$output
  if [[ $rc -ne $expected ]]; then
    say "FAIL $name: exit $rc, expected $expected"
    failures=$((failures + 1))
    CHECK_OK=0
    return 0
  fi
  say "ok   $name"
  CHECK_OK=1
}

check "the root has no OpenImageIO, Embree, OSMesa or glvnd libEGL" 0 \
  "! ls /usr/lib/x86_64-linux-gnu | grep -E '^lib(OpenImageIO|embree|OSMesa|EGL\\.so|tbb)'"
check "ldd: every library resolves, from the bundle or glibc" 0 \
  "LD_LIBRARY_PATH=$b/lib:$b/lib/glvnd ldd $b/bin/chcrt | tee /dev/stderr | { ! grep -q 'not found'; } &&
   LD_LIBRARY_PATH=$b/lib:$b/lib/glvnd ldd $b/bin/chcrt | grep '=>' | grep -v -E '$b/|/libc\\.so|/libm\\.so|/ld-linux' | { ! grep .; }"
check "run.sh info" 0 "$b/run.sh info --scene city:100k -q"
if ((CHECK_OK)) && ! grep -q "llvmpipe" <<<"$LAST_OUTPUT"; then say "FAIL run.sh info: no llvmpipe renderer"; failures=$((failures + 1)); fi
check "run.sh render PNG and EXR" 0 \
  "$b/run.sh render --scene city:100k --width 256 --height 144 --spp 2 -o city.png &&
   $b/run.sh render --scene interior:100k --width 128 --height 96 --spp 1 -o interior.exr &&
   python3 -c 'import sys; d=open(\"city.png\",\"rb\").read(8); e=open(\"interior.exr\",\"rb\").read(4); sys.exit(0 if d==b\"\\x89PNG\\r\\n\\x1a\\n\" and e==bytes([0x76,0x2f,0x31,1]) else 1)'"
check "run.sh verify: GLSL against Embree" 0 \
  "$b/run.sh verify --scene city:100k --width 160 --height 90 --frames spread:2 --ray-type primary,shadow,ao,diffuse -q"
check "run.sh verify --method chcrt: CHC+RT against pure BVH" 0 \
  "$b/run.sh verify --method chcrt --scene city:100k --width 160 --height 90 --frames spread:2 --ray-type primary,shadow,ao,diffuse -q"
check "run.sh bench" 0 \
  "$b/run.sh bench --scene city:100k --width 160 --height 90 --frames 0-1 --runs 1 --ray-type primary,shadow --method bvh,chcrt,embree -q --json bench.json --markdown bench.md"
check "run.sh info --gl osmesa without OSMesa: exit 3" 3 "$b/run.sh info --no-scene --gl osmesa -q"
if ((CHECK_OK)); then
  if [[ $(grep -c . <<<"$LAST_OUTPUT") -ne 1 || $LAST_OUTPUT != *"cannot load OSMesa"* ]]; then
    say "FAIL --gl osmesa: expected one line naming OSMesa, got: $LAST_OUTPUT"; failures=$((failures + 1))
  fi
fi
check "run.sh under the bundle's own glibc and loader (CHCRT_BUNDLE_GLIBC=1)" 0 \
  "CHCRT_BUNDLE_GLIBC=1 CHCRT_BUNDLE_PRINT=1 $b/run.sh info --no-scene -q"
check "run.sh from a symlink in another directory" 0 "ln -sf $b/run.sh /tmp/work/chcrt && ./chcrt methods >/dev/null"
if [[ ${CHCRT_TEST_BUNDLE_GPU_CHECK:-1} == 1 ]]; then
  check "gpu_check.sh --quick" 0 "bash $b/gpu_check.sh --quick ${CHCRT_TEST_BUNDLE_GPU_CHECK_ARGS:-} /tmp/work/gpu_check"
  rm -rf "$out/gpu_check"
  cp -r "$root/tmp/work/gpu_check" "$out/gpu_check"
  grep -q "| info | ok |" "$out/gpu_check/summary.md" || { say "FAIL gpu_check: its info step did not succeed"; failures=$((failures + 1)); }
fi
cp "$root/tmp/work/bench.md" "$root/tmp/work/city.png" "$out/" 2>/dev/null || true

if ((failures)); then
  say "FAIL: $failures check(s) failed; $log"
  exit 1
fi
say "PASS: the bundle runs in a minimal Debian root on llvmpipe; $log"
