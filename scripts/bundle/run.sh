#!/usr/bin/env bash
# Runs the bundle's chcrt with this script's arguments (docs/gpu.md), from any working directory: the bundle's
# libraries come first on LD_LIBRARY_PATH (lib/, then glvnd's libEGL in lib/glvnd/); the GL driver (its EGL vendor
# library, found by glvnd through /usr/share/glvnd/egl_vendor.d/) and glibc are the machine's.
# When the machine's glibc is older than GLIBC_REQUIRED, chcrt runs under the bundle's own glibc and dynamic loader
# (lib/glibc/) instead. Environment:
#   CHCRT_BUNDLE_GLIBC=1    use the bundle's glibc even when the machine's is new enough (0: never);
#   CHCRT_SYSTEM_EGL=1      use the machine's libEGL.so.1 instead of the bundle's glvnd copy;
#   CHCRT_BUNDLE_PRINT=1    print the command (loader, library path) on stderr before running it;
#   CHCRT_DRIVER_PREFIXES   where to look for a GL driver installed outside the standard places when
#                           /etc/glvnd/egl_vendor.d and /usr/share/glvnd/egl_vendor.d hold no EGL vendor file
#                           (default /usr/local/nvidia, where GPU containers mount the NVIDIA driver);
#   CHCRT_GLVND_VENDOR_DIRS the folders glvnd reads by default (tests/app/bundle_run_test.sh points them elsewhere).
# Bash only: no other program is needed.
set -euo pipefail
GLIBC_REQUIRED=@GLIBC_REQUIRED@
source=${BASH_SOURCE[0]}
while [[ -L $source ]]; do # a symlink to run.sh: find the bundle through it
  target=$(readlink "$source")
  [[ $target == /* ]] && source=$target || source=${source%/*}/$target
done
[[ $source == */* ]] || source=./$source
here=$(cd "${source%/*}" && pwd -P)
lib=$here/lib
path=$lib
[[ ${CHCRT_SYSTEM_EGL:-0} == 1 ]] || path=$path:$lib/glvnd

# glvnd's libEGL reads vendor files only from /etc/glvnd/egl_vendor.d and /usr/share/glvnd/egl_vendor.d unless told
# otherwise. A driver mounted elsewhere (GPU containers: /usr/local/nvidia/share/glvnd/egl_vendor.d, with its
# libraries in /usr/local/nvidia/lib64) is then invisible, and EGL finds no device; point glvnd and the loader there.
vendor_files() { compgen -G "$1/*.json" >/dev/null; }
standard_vendor=0
for dir in ${CHCRT_GLVND_VENDOR_DIRS:-/etc/glvnd/egl_vendor.d /usr/share/glvnd/egl_vendor.d}; do
  vendor_files "$dir" && standard_vendor=1
done
if [[ -z ${__EGL_VENDOR_LIBRARY_FILENAMES:-}${__EGL_VENDOR_LIBRARY_DIRS:-} && $standard_vendor == 0 ]]; then
  for prefix in ${CHCRT_DRIVER_PREFIXES:-/usr/local/nvidia}; do
    vendor_files "$prefix/share/glvnd/egl_vendor.d" || continue
    export __EGL_VENDOR_LIBRARY_DIRS=$prefix/share/glvnd/egl_vendor.d
    for dir in "$prefix/lib64" "$prefix/lib"; do [[ -d $dir ]] && path=$path:$dir; done
    break
  done
fi

# glibc version of this machine: from its loader's own report (bash and the loader only), else assumed new enough.
machine_glibc() {
  local loader version
  for loader in /lib64/ld-linux-x86-64.so.2 /lib/x86_64-linux-gnu/ld-linux-x86-64.so.2; do
    [[ -x $loader ]] || continue
    version=$("$loader" --version 2>/dev/null || true)
    if [[ $version =~ ([0-9]+)\.([0-9]+) ]]; then echo "${BASH_REMATCH[1]}.${BASH_REMATCH[2]}"; return; fi
  done
  echo 999.0
}
older() { # older A B: version A < version B
  local a_major=${1%%.*} a_minor=${1#*.} b_major=${2%%.*} b_minor=${2#*.}
  ((a_major < b_major || (a_major == b_major && ${a_minor%%.*} < ${b_minor%%.*})))
}
use_bundled_glibc=${CHCRT_BUNDLE_GLIBC:-}
if [[ -z $use_bundled_glibc ]]; then
  use_bundled_glibc=0
  older "$(machine_glibc)" "$GLIBC_REQUIRED" && use_bundled_glibc=1
fi
if [[ $use_bundled_glibc == 1 ]]; then
  command=("$lib/glibc/ld-linux-x86-64.so.2" --library-path "$lib/glibc:$path${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$here/bin/chcrt" "$@")
else
  export LD_LIBRARY_PATH=$path${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  command=("$here/bin/chcrt" "$@")
fi
[[ ${CHCRT_BUNDLE_PRINT:-0} == 1 ]] && echo "run.sh: ${__EGL_VENDOR_LIBRARY_DIRS:+__EGL_VENDOR_LIBRARY_DIRS=$__EGL_VENDOR_LIBRARY_DIRS }${LD_LIBRARY_PATH:+LD_LIBRARY_PATH=$LD_LIBRARY_PATH }${command[*]}" >&2
exec "${command[@]}"
