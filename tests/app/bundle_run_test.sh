#!/usr/bin/env bash
# The bundle's run.sh (scripts/bundle/run.sh, docs/gpu.md): where it finds a GL driver mounted outside glvnd's
# standard vendor folders. A fake bundle whose bin/chcrt prints the environment it was given; glvnd's standard
# folders pointed (CHCRT_GLVND_VENDOR_DIRS) at temporary ones.
set -euo pipefail
source_dir=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bundle=$work/bundle
mkdir -p "$bundle/bin" "$bundle/lib/glvnd" "$work/standard" "$work/empty/share/glvnd/egl_vendor.d" \
  "$work/driver/share/glvnd/egl_vendor.d" "$work/driver/lib64"
sed -e 's/@GLIBC_REQUIRED@/2.0/' "$source_dir/scripts/bundle/run.sh" >"$bundle/run.sh"
printf '#!/usr/bin/env bash\necho "dirs=${__EGL_VENDOR_LIBRARY_DIRS:-} files=${__EGL_VENDOR_LIBRARY_FILENAMES:-} path=$LD_LIBRARY_PATH"\n' \
  >"$bundle/bin/chcrt"
chmod 755 "$bundle/run.sh" "$bundle/bin/chcrt"
echo '{"file_format_version": "1.0.0", "ICD": {"library_path": "libEGL_fake.so.0"}}' \
  >"$work/driver/share/glvnd/egl_vendor.d/10_fake.json"
failures=0
run() { # run EXPECTED_PATTERN ENV...: run.sh's output must match the pattern
  local pattern=$1 out
  shift
  out=$(env -u __EGL_VENDOR_LIBRARY_DIRS -u __EGL_VENDOR_LIBRARY_FILENAMES CHCRT_BUNDLE_GLIBC=0 \
    CHCRT_GLVND_VENDOR_DIRS="$work/standard" "$@" "$bundle/run.sh")
  if [[ $out =~ $pattern ]]; then echo "ok: $*"; else echo "FAILED: $* printed: $out (expected /$pattern/)"; failures=$((failures + 1)); fi
}
# No vendor file in the standard folders: the first prefix with one is chosen, its lib64 joins the library path.
run "^dirs=$work/driver/share/glvnd/egl_vendor.d files= path=$bundle/lib:$bundle/lib/glvnd:$work/driver/lib64\$" \
  CHCRT_DRIVER_PREFIXES="$work/missing $work/empty $work/driver"
# A prefix without a vendor file is not chosen.
run "^dirs= files= path=$bundle/lib:$bundle/lib/glvnd\$" CHCRT_DRIVER_PREFIXES="$work/empty"
# The user's own vendor settings win.
run "^dirs=/mine files= " __EGL_VENDOR_LIBRARY_DIRS=/mine CHCRT_DRIVER_PREFIXES="$work/driver"
run "^dirs= files=/mine.json " __EGL_VENDOR_LIBRARY_FILENAMES=/mine.json CHCRT_DRIVER_PREFIXES="$work/driver"
# A vendor file in a standard folder: glvnd finds the driver itself; nothing is set.
cp "$work/driver/share/glvnd/egl_vendor.d/10_fake.json" "$work/standard/"
run "^dirs= files= path=$bundle/lib:$bundle/lib/glvnd\$" CHCRT_DRIVER_PREFIXES="$work/driver"
exit $((failures > 0))
