#!/usr/bin/env bash
# Installs megavox's build and test dependencies from Debian 12 packages (idempotent, non-interactive).
#   scripts/setup.sh                          what building and testing need
#   scripts/setup.sh --bench                  also the baseline-only libraries the benchmarks compare against
#   scripts/setup.sh --print-packages [--bench]   print that package list, one per line; install nothing
set -euo pipefail

bench=0 print=0
for arg in "$@"; do
  case $arg in
    --bench) bench=1 ;;
    --print-packages) print=1 ;;
    *) echo "setup: unknown option '$arg' (use --bench, --print-packages)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build pkg-config git
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo     # OpenCL, PoCL (the CPU device)
  libvulkan-dev mesa-vulkan-drivers glslang-tools vulkan-tools   # Vulkan, lavapipe, GLSL -> SPIR-V
  libcli11-dev nlohmann-json3-dev libtbb-dev libgtest-dev libgmock-dev libxxhash-dev
  libassimp-dev libopenvdb-dev libimath-dev                     # OBJ, glTF, FBX, STL, ... meshes; .vdb volumes
  libboost-dev                                                  # OpenVDB's headers include Boost (not a dependency of libopenvdb-dev)
  libnanovdb-dev                                                # NanoVDB export
  libpng-dev                                                    # rendered pictures
  libgmp-dev                                                    # tests: exact rational voxelization oracle
)
if ((bench)); then
  # Baseline-only libraries: built into the megavox_baselines target only (CMake option MEGAVOX_BASELINES).
  # Boost.Sort (block_indirect_sort) comes with libboost-dev above.
  packages+=(libembree-dev)   # Embree 3, the triangle ray-tracing baseline of bench trace
  packages+=(libips4o-dev)    # ips4o::parallel::sort (header-only; OpenMP threads), a sort baseline of bench sort
  packages+=(libhwy-dev)      # Highway's vqsort (libhwy_contrib), a sort baseline of bench sort
  # voxcom, the peer of bench build, is built apart from megavox (scripts/bench.sh) where the shared folder holds
  # it; it also needs assimp, TBB and CLI11, listed above.
  if [[ -d "$(dirname "$0")/../../shared/peers/voxcom" ]]; then
    packages+=(libspdlog-dev libfmt-dev libglm-dev libabsl-dev libfreeimage-dev libfreeimageplus-dev)
  fi
fi

if ((print)); then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""
  [[ $(id -u) -eq 0 ]] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
