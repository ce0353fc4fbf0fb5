#!/usr/bin/env bash
# libvbl set-up: installs missing Debian 12 packages, builds, then either renders the demo
# scene (`./setup.sh demo`) or runs the whole test suite (`./setup.sh test`).
set -euo pipefail
cd "$(dirname "$0")"

mode="${1:-demo}"
jobs="$(nproc 2>/dev/null || echo 2)"

packages=(
  cmake make gcc g++ pkg-config python3 python3-numpy python3-colormath
  libopenvdb-dev libnanovdb-dev libopenvdb-tools libnanovdb-tools libblosc-dev zlib1g-dev
  libboost-iostreams-dev libtbb-dev libopenexr-dev libopencolorio-dev libembree-dev libosd-dev
  libcjson-dev libpng-dev libcmocka-dev openimageio-tools libassimp-dev
)
# only for `./setup.sh test`: the Slurm integration test (tests/pipeline), benchmark plots and the
# documentation site (tests/docs: MkDocs + Doxygen); blender, python3-openimageio and
# python3-openvdb also for the Cycles reference kit (bench/race_cycles)
test_packages=(slurm-wlm slurmctld slurmd munge python3-matplotlib mkdocs doxygen blender python3-openimageio python3-openvdb)

install_missing_packages() {
  local missing=()
  for package in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

build() {  # build DIR [cmake options...]
  local dir="$1"; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j"$jobs"
}

[ "$mode" = test ] && packages+=("${test_packages[@]}")
install_missing_packages
case "$mode" in
  demo)
    build build
    mkdir -p out
    ./samples/demo.sh build out
    ;;
  test)
    build build
    ctest --test-dir build --output-on-failure -j"$jobs"
    # Second build with AddressSanitizer + UndefinedBehaviorSanitizer; long statistical renders
    # (label 'slow') and the documentation checks (label 'docs', no C code) run only in the
    # optimized build above, so this build leaves out the slow tests' executables
    # (VBL_BUILD_SLOW_TESTS=OFF), the benchmarks, and reuses the data generators.
    build build-asan -DVBL_SANITIZE=ON -DVBL_BUILD_BENCH=OFF -DVBL_BUILD_SLOW_TESTS=OFF \
      -DVBL_GENERATORS_FROM="$PWD/build"
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      ctest --test-dir build-asan --output-on-failure -j"$jobs" -LE "slow|docs"
    ;;
  *)
    echo "usage: ./setup.sh demo|test" >&2
    exit 2
    ;;
esac
