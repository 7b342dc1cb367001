#!/usr/bin/env bash
# Sets up a Debian 12 machine for chcrt and builds it:
#   1. installs the Debian packages the build and `chcrt report` need (python3-matplotlib for its figures,
#      chromium for its page's test; clang-14 and libclang-rt-14-dev for the libFuzzer harnesses that
#      scripts/fuzz.sh builds; glslang-tools for the test that validates every shader variant with
#      glslangValidator), only those that are missing (apt-get; as root, or through sudo when
#      available — otherwise it prints the apt-get command to run and stops);
#   2. configures (CMake + Ninja, Release) into build/ and builds everything.
# Options (environment): CHCRT_BUILD_DIR (default build), CHCRT_WERROR=ON (warnings are errors; CI sets it),
# CHCRT_SANITIZE=ON (AddressSanitizer + UndefinedBehaviorSanitizer), CHCRT_CMAKE_ARGS (extra CMake arguments),
# CHCRT_BUILD_TARGET (build only this target instead of everything).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config git
  libglfw3-dev libosmesa6-dev libegl-dev libegl1-mesa-dev libgl-dev libgl1-mesa-dri libopengl-dev
  libglm-dev libtinygltf-dev libstb-dev libtinyexr-dev libimgui-dev libopenimageio-dev openimageio-tools
  libembree-dev libtbb-dev libgtest-dev nlohmann-json3-dev libcli11-dev libmeshoptimizer-dev
  xvfb xauth glslang-tools
  python3-matplotlib chromium
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [[ $(id -u) -eq 0 ]]; then
    apt_get=(apt-get)
  elif command -v sudo >/dev/null; then
    apt_get=(sudo apt-get)
  else
    echo "setup: not root and no sudo; run as root: apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${apt_get[@]}" update -qq
  "${apt_get[@]}" install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build_dir=${CHCRT_BUILD_DIR:-build}
werror=${CHCRT_WERROR:-OFF}
sanitize=${CHCRT_SANITIZE:-OFF}
# shellcheck disable=SC2086
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=${CHCRT_BUILD_TYPE:-Release} \
  -DCHCRT_WERROR="$werror" -DCHCRT_SANITIZE="$sanitize" ${CHCRT_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j"$(nproc)" ${CHCRT_BUILD_TARGET:+--target "$CHCRT_BUILD_TARGET"}
