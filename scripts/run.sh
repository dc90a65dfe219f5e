#!/usr/bin/env bash
# Sets up, builds and runs megavox's main job on its built-in default: list the compute devices, then
# benchmark the radix sort that every later stage builds on against std::sort and a parallel CPU sort.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --bench
scripts/build.sh
build/megavox devices
build/megavox bench sort --n 16M
