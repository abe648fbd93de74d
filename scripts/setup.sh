# scripts/setup.sh — shared by scripts/demo and scripts/test: installs the Debian packages
# softpbr needs when they are missing, then configures and builds what is stale.
# Sourced, not run. Honours BUILD_DIR (default: build) and BUILD_TYPE (default: Release).
set -euo pipefail

SOFTPBR_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-$SOFTPBR_ROOT/build}
BUILD_TYPE=${BUILD_TYPE:-Release}

# Debian 12 package names. Keep in step with the find_package calls in CMakeLists.txt.
# The libraries and the examples (what ./scripts/demo builds: SOFTPBR_CORE_ONLY=1) ...
SOFTPBR_PACKAGES=(g++ make cmake pkg-config libglm-dev libtinyobjloader-dev libstb-dev nlohmann-json3-dev
                  libtinyexr-dev libspng-dev libxxhash-dev libtinygltf-dev libmeshoptimizer-dev libdraco-dev
                  libwebp-dev libavif-dev libzstd-dev ccache)
# ... and the tests, the command, the benchmarks, the viewer and the Python module (everything
# else: ./scripts/test). Measured on a bare Debian 12 (minbase + git): the core list is about
# 90 packages and 100 MB, the whole one about 295 packages and 195 MB (xvfb, SDL2, Python).
if [ -z "${SOFTPBR_CORE_ONLY:-}" ]; then
  SOFTPBR_PACKAGES+=(doctest-dev libbenchmark-dev libcli11-dev libsdl2-dev xvfb xauth
                     pybind11-dev python3-dev python3-numpy python3-pytest
                     python3-distributed)  # python3-distributed (with python3-dask): the Dask example's test
fi
# Scripts that source this file may ask for more (.ci/matrix: clang; .ci/fuzz: clang and libclang-rt-14-dev) in SOFTPBR_EXTRA_PACKAGES.
SOFTPBR_PACKAGES+=(${SOFTPBR_EXTRA_PACKAGES[@]+"${SOFTPBR_EXTRA_PACKAGES[@]}"})

softpbr_install_packages() {
  local missing=() p
  for p in "${SOFTPBR_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -eq 0 ]; then
    echo "softpbr: installing missing Debian packages: ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  else
    echo "softpbr: missing Debian packages. Install them with:" >&2
    echo "  sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
}

# ccache (Debian's) for every build folder these scripts configure: a compilation that any
# build folder or clone of this machine made before, with the same flags and sources, is
# copied from the cache instead of compiled again (docs/design.md, Tests and CI). The cache
# lives outside the clone (ccache's default, ~/.cache/ccache); CCACHE_BASEDIR makes the
# paths it hashes relative to the clone, so two clones in different folders share it, and
# CCACHE_NOHASHDIR leaves the build folder out of the hash of builds with debug information.
# CMake takes the launcher from the environment when it configures a new build folder.
# SOFTPBR_NO_CCACHE=1 turns it off.
softpbr_use_ccache() {
  [ -z "${SOFTPBR_NO_CCACHE:-}" ] && command -v ccache >/dev/null || return 0
  export CMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}
  export CMAKE_C_COMPILER_LAUNCHER=${CMAKE_C_COMPILER_LAUNCHER:-ccache}
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$SOFTPBR_ROOT}
  export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
  # Every configuration .ci/run builds (Release, Debug+sanitizers, Clang, native, AArch64,
  # fuzz, TSan) fits; ccache evicts the oldest objects beyond it.
  export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-20G}
}

# softpbr_build [TARGET...]: builds the targets named (and what they need), or everything.
softpbr_build() {
  # Configure once (again if a configure failed); the build then reruns CMake itself when a
  # CMakeLists.txt changes and rebuilds only what is stale.
  # SOFTPBR_CORE_ONLY (./scripts/demo) configures without the parts whose packages it did
  # not install; a later full build (./scripts/test) turns them on again.
  local parts=ON
  [ -n "${SOFTPBR_CORE_ONLY:-}" ] && parts=OFF
  local options=(-DSOFTPBR_BUILD_TESTS=$parts -DSOFTPBR_BUILD_CLI=$parts -DSOFTPBR_BUILD_BENCHMARKS=$parts
                 -DSOFTPBR_BUILD_PYTHON=$parts)
  if [ ! -f "$BUILD_DIR/Makefile" ] ||
     { [ "$parts" = ON ] && grep -q '^SOFTPBR_BUILD_TESTS:BOOL=OFF' "$BUILD_DIR/CMakeCache.txt" 2>/dev/null; }; then
    cmake -S "$SOFTPBR_ROOT" -B "$BUILD_DIR" -G "Unix Makefiles" -DCMAKE_BUILD_TYPE="$BUILD_TYPE" "${options[@]}" >&2
  fi
  local targets=() t
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$BUILD_DIR" ${targets[@]+"${targets[@]}"} --parallel "$(nproc)" >&2
}

softpbr_install_packages
softpbr_use_ccache
