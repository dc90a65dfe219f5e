#!/usr/bin/env bash
# Configures and builds megavox (Release) into build/. Used by run.sh, test.sh and bench.sh.
# Usage: scripts/build.sh [-DOPTION=VALUE ...]
# Configure runs on every call (CMake keeps it incremental), so a package installed since the last build
# is found, and options given here (e.g. -DMEGAVOX_BASELINES=OFF) take effect.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
# A build tree keeps its generator: only pick Ninja for a new one.
[[ ! -f build/CMakeCache.txt ]] && command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build --parallel "$(nproc)"
