#!/usr/bin/env bash
# Builds the travelling configuration of chcrt and packs it into DIR/chcrt-gpu-<commit>.tar.gz (docs/gpu.md):
# a bundle that runs the headless commands on a Linux x86-64 machine with a GPU driver and nothing else installed
# (no Debian packages, no GL client libraries, no network).
#   - build: Release, CHCRT_WITH_OIIO=OFF (the built-in PNG/JPEG/HDR/EXR codec), no viewer, no tests, in its own
#     build directory (CHCRT_BUNDLE_BUILD_DIR, default build-bundle); OSMesa is never linked (dlopen for --gl osmesa);
#   - bin/chcrt, stripped, shaders embedded (checked: the binary must run with no source tree);
#   - lib/: every shared library `ldd bin/chcrt` lists except glibc and the GL/EGL libraries (Embree, TBB, tinygltf,
#     stb, tinyexr, zlib, libstdc++, libgcc_s), stripped;
#   - lib/glvnd/: glvnd's libEGL.so.1 and libGLdispatch.so.0 from Debian's libegl1 and libglvnd0 (apt-get download,
#     dpkg -x); the GPU driver's EGL vendor library is the target's (glvnd finds it through
#     /usr/share/glvnd/egl_vendor.d/ there);
#   - lib/glibc/: this machine's glibc and dynamic loader, used by run.sh only when the target's glibc is older than
#     the one the binaries need (GLIBC_REQUIRED in run.sh);
#   - run.sh (runs bin/chcrt with its arguments, from any directory), gpu_check.sh (docs/gpu.md), MANIFEST.txt.
# The last line printed is the tarball's path. Fails when the tarball exceeds 48 MiB (CHCRT_BUNDLE_MAX_MIB).
# Needs root or sudo only when packages are missing (scripts/setup.sh installs them); apt-get download needs the
# Debian mirror once (the packages are kept in the build directory).
set -euo pipefail
if [[ $# -ne 1 || $1 == -* ]]; then
  echo "usage: scripts/gpu_bundle.sh DIR   (writes DIR/chcrt-gpu-<commit>.tar.gz and prints its path)" >&2
  exit 2
fi
mkdir -p "$1"
out_dir=$(cd "$1" && pwd -P)
cd "$(dirname "$0")/.."
root=$(pwd -P)
build=${CHCRT_BUNDLE_BUILD_DIR:-build-bundle}
max_mib=${CHCRT_BUNDLE_MAX_MIB:-48}
log() { echo "gpu_bundle: $*" >&2; }

# 1. The travelling build (scripts/setup.sh installs what is missing and configures with these arguments).
log "building the travelling configuration in $build"
CHCRT_BUILD_DIR=$build CHCRT_BUILD_TARGET=chcrt \
  CHCRT_CMAKE_ARGS="-DCHCRT_WITH_OIIO=OFF -DCHCRT_BUILD_VIEWER=OFF -DCHCRT_BUILD_TESTS=OFF ${CHCRT_CMAKE_ARGS:-}" \
  scripts/setup.sh >&2
binary=$build/bin/chcrt
commit=$(git -C "$root" describe --always --dirty --abbrev=10 2>/dev/null || echo unknown)
name=chcrt-gpu-$commit
stage_root=$(mktemp -d "${TMPDIR:-/tmp}/chcrt_bundle.XXXXXX")
trap 'rm -rf "$stage_root"' EXIT
stage=$stage_root/$name
mkdir -p "$stage/bin" "$stage/lib/glvnd" "$stage/lib/glibc"

# 2. The binary and every non-glibc, non-GL library it loads.
cp "$binary" "$stage/bin/chcrt"
strip --strip-unneeded "$stage/bin/chcrt"
is_glibc() { [[ $1 =~ ^(libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl|ld-linux-x86-64)\.so ]]; }
is_gl() { [[ $1 =~ ^lib(EGL|GL|GLX|GLdispatch|OpenGL|GLESv[12]_CM|GLESv2|OSMesa|gbm)[._] ]]; }
ldd_out=$(ldd "$binary")
if grep -q "not found" <<<"$ldd_out"; then
  log "ldd $binary: libraries not found:"; grep "not found" <<<"$ldd_out" >&2; exit 1
fi
if grep -qE "libOpenImageIO|libOSMesa|libglfw|libX11" <<<"$ldd_out"; then
  log "$binary links a library the travelling build must not need:"; grep -E "libOpenImageIO|libOSMesa|libglfw|libX11" <<<"$ldd_out" >&2; exit 1
fi
bundled=()
while read -r soname _ path _; do
  [[ -n ${path:-} && -f $path ]] || continue
  is_glibc "$soname" && continue
  is_gl "$soname" && continue
  cp -L "$path" "$stage/lib/$soname"
  chmod u+w "$stage/lib/$soname"
  strip --strip-unneeded "$stage/lib/$soname" 2>/dev/null || true
  package=$( (dpkg -S "$path" || dpkg -S "$(readlink -f "$path")" || dpkg -S "/usr$path") 2>/dev/null | head -n 1 | cut -d: -f1)
  bundled+=("$soname <- $path (${package:-no Debian package})")
done < <(grep "=>" <<<"$ldd_out")
grep -q "libEGL.so.1" <<<"$ldd_out" || { log "$binary does not link libEGL.so.1"; exit 1; }

# 3. glvnd's libEGL and libGLdispatch from Debian's packages (kept in the build directory for later runs).
debs=$build/debs
mkdir -p "$debs"
fetched=()
for package in libegl1 libglvnd0; do
  version=$(dpkg-query -W -f='${Version}' "$package" 2>/dev/null || true)
  deb=
  for candidate in "$debs/${package}_"*.deb; do # a package downloaded before, of the version installed here
    [[ -f $candidate && $(dpkg-deb -f "$candidate" Version) == "$version" ]] && deb=$candidate
  done
  if [[ -z $deb ]]; then
    # apt-get download runs as _apt where it can; a directory _apt cannot write only draws a warning (as root).
    (cd "$debs" && apt-get download -q "$package${version:+=$version}" >&2) ||
      { log "apt-get download $package failed (the Debian mirror must be reachable once)"; exit 1; }
    deb=$(ls -t "$debs/${package}_"*.deb | head -n 1)
  fi
  fetched+=("$(basename "$deb")")
  rm -rf "$debs/x"; mkdir -p "$debs/x"
  dpkg -x "$deb" "$debs/x"
  case $package in
    libegl1) cp -L "$debs/x/usr/lib/x86_64-linux-gnu/libEGL.so.1" "$stage/lib/glvnd/" ;;
    libglvnd0) cp -L "$debs/x/usr/lib/x86_64-linux-gnu/libGLdispatch.so.0" "$stage/lib/glvnd/" ;;
  esac
done
rm -rf "$debs/x"

# 4. glibc and its loader, for a target whose glibc is older than the one the binaries were linked against.
glibc_required=$(for f in "$stage/bin/chcrt" "$stage"/lib/*.so* "$stage"/lib/glvnd/*.so*; do
    objdump -T "$f" 2>/dev/null | grep -o 'GLIBC_[0-9.]*' || true
  done | sed 's/GLIBC_//' | sort -t. -k1,1n -k2,2n -u | tail -n 1)
for soname in ld-linux-x86-64.so.2 libc.so.6 libm.so.6 libmvec.so.1 libpthread.so.0 libdl.so.2 librt.so.1 \
              libresolv.so.2 libutil.so.1 libanl.so.1; do
  path=$(ls /lib/x86_64-linux-gnu/"$soname" /lib64/"$soname" 2>/dev/null | head -n 1 || true)
  [[ -n $path ]] && cp -L "$path" "$stage/lib/glibc/$soname"
done
glibc_bundled=$(dpkg-query -W -f='${Version}' libc6)

# 5. run.sh, gpu_check.sh, the manifest.
sed -e "s/@GLIBC_REQUIRED@/$glibc_required/" scripts/bundle/run.sh >"$stage/run.sh"
cp scripts/gpu_check.sh "$stage/gpu_check.sh"
chmod 755 "$stage/run.sh" "$stage/gpu_check.sh" "$stage/bin/chcrt"
{
  echo "chcrt GPU bundle (docs/gpu.md), commit $commit, built $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(. /etc/os-release; echo "$PRETTY_NAME")"
  echo "build: $build, Release, -DCHCRT_WITH_OIIO=OFF -DCHCRT_BUILD_VIEWER=OFF -DCHCRT_BUILD_TESTS=OFF ${CHCRT_CMAKE_ARGS:-}"
  echo "glibc needed: $glibc_required (bundled in lib/glibc: $glibc_bundled, used only when the target's is older)"
  echo "glvnd: ${fetched[*]}"
  echo "libraries:"; printf '  %s\n' "${bundled[@]}"
  echo "files:"; (cd "$stage" && find . -type f -printf '  %p %s\n' | sort)
} >"$stage/MANIFEST.txt"

# The bundle must run without the source tree: shaders embedded (a render from an empty directory compiles them from
# the binary; CHCRT_SHADER_DIR is unset), only its own libraries besides glibc and the GL driver (this machine's
# Mesa here: glvnd finds it through /usr/share/glvnd/egl_vendor.d/).
grep -aq "render/trace_bvh.frag.glsl" "$stage/bin/chcrt" || { log "the shaders are not embedded in $binary"; exit 1; }
mkdir -p "$stage_root/check"
if ! (cd "$stage_root/check" && env -i PATH=/usr/bin:/bin "$stage/run.sh" render --scene one-triangle --width 16 \
      --height 16 --spp 1 -q -o check.png >&2 && [[ -s check.png ]]); then
  log "the staged bundle does not run: run.sh render failed outside the source tree"; exit 1
fi
rm -rf "$stage_root/check"

tarball=$out_dir/$name.tar.gz
tar -C "$stage_root" --owner=0 --group=0 --numeric-owner -czf "$tarball.tmp" "$name"
mv "$tarball.tmp" "$tarball"
bytes=$(stat -c %s "$tarball")
unpacked=$(du -sb "$stage" | cut -f1)
log "$(awk -v t="$bytes" -v u="$unpacked" -v n="${#bundled[@]}" -v f="$(basename "$tarball")" \
  'BEGIN { printf "%s: %.1f MiB (unpacked %.1f MiB), %d libraries + glvnd + glibc", f, t / 1048576, u / 1048576, n }')"
if ((bytes > max_mib * 1048576)); then
  log "the tarball exceeds $max_mib MiB"; exit 1
fi
echo "$tarball"
