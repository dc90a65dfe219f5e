#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (every kernel test on every OpenCL and Vulkan device found).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh -DMEGAVOX_BASELINES=OFF   # the test path provably needs no baseline library
cd build
ctest --output-on-failure --parallel "$(nproc)"
