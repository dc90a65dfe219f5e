#!/usr/bin/env bash
# Installs megavox's build and test dependencies from Debian 12 packages (idempotent, non-interactive).
#   scripts/setup.sh                          what building and testing need
#   scripts/setup.sh --bench                  also the baseline-only libraries the benchmarks compare against
#   scripts/setup.sh --viewer                 also Chromium, for the test that renders a 3D Tiles tileset
#   scripts/setup.sh --fuzz                   also clang and its libFuzzer/ASan/UBSan runtime (scripts/fuzz.sh)
#   scripts/setup.sh --print-packages [--bench] [--viewer] [--fuzz]   print that package list, one per line; install nothing
# Then, where npm is, the pinned npm packages of the 3D Tiles checks (tests/js, `npm ci`).
set -euo pipefail

bench=0 viewer=0 fuzz=0 print=0
for arg in "$@"; do
  case $arg in
    --bench) bench=1 ;;
    --viewer) viewer=1 ;;
    --fuzz) fuzz=1 ;;
    --print-packages) print=1 ;;
    *) echo "setup: unknown option '$arg' (use --bench, --viewer, --fuzz, --print-packages)" >&2; exit 2 ;;
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
  libpng-dev                                                    # rendered pictures; PNG images and seed maps in
  libjpeg62-turbo-dev                                           # JPEG photographs in (masks)
  libgmp-dev                                                    # tests: exact rational voxelization oracle
  libcpp-httplib-dev                                            # megavox serve: the HTTP server (and the load test's client)
  libminizip-dev libssl-dev                                     # megavox serve: 3D Tiles archives (.3tz: ZIP, MD5 index)
  curl jq                                                       # tests: the serve session as the README runs it
  python3-dev pybind11-dev python3-numpy python3-pytest         # the Python module (python/) and its tests
  libopenmpi-dev openmpi-bin                                    # builds over MPI ranks (mpirun -np N megavox build)
  libproj-dev proj-data                                         # 3D Tiles placed on the globe (EPSG:4978; proj.db at run time)
  libmeshoptimizer-dev                                          # 3D Tiles 1.1: EXT_meshopt_compression of glTF point tiles
)
# Node runs the independent 3D Tiles reader (tests/js). A machine that has node and npm already (another
# distribution's build) keeps them: Debian's npm would conflict with it.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi
if ((viewer)); then
  packages+=(chromium)   # headless, software GL (SwiftShader): tests/js/render_tileset.mjs, cesium_tileset.mjs
fi
if ((fuzz)); then
  # clang 14 with libFuzzer and the sanitizer runtimes. clang only *recommends* the runtime package, and
  # installs here skip recommendations: it must be named.
  packages+=(clang libclang-rt-14-dev)
fi
if ((bench)); then
  # Baseline-only libraries: built into the megavox_baselines target only (CMake option MEGAVOX_BASELINES).
  # Boost.Sort (block_indirect_sort) comes with libboost-dev above.
  packages+=(libembree-dev)   # Embree 3, the triangle ray-tracing baseline of bench trace
  packages+=(libips4o-dev)    # ips4o::parallel::sort (header-only; OpenMP threads), a sort baseline of bench sort
  packages+=(libhwy-dev)      # Highway's vqsort (libhwy_contrib), a sort baseline of bench sort
  packages+=(libopencv-imgproc-dev)  # OpenCV 4.6 cv::grabCut, the GrabCut baseline of bench mask
  packages+=(assimp-testmodels)  # assimp's test models: the textured Cesium Milk Truck (glTF) of bench attributes
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

# The 3D Tiles checks' npm packages, exactly as package-lock.json pins them; skipped when that lock is what
# was installed last. A failure is a warning: the tests that need them then say they were not run.
js="$(dirname "$0")/../tests/js"
if command -v npm >/dev/null && ! cmp -s "$js/package-lock.json" "$js/node_modules/.megavox-lock"; then
  echo "setup: installing the npm packages of tests/js" >&2
  if (cd "$js" && npm ci --no-audit --no-fund --loglevel=error >/dev/null); then
    cp "$js/package-lock.json" "$js/node_modules/.megavox-lock"
  else
    echo "setup: warning: npm ci in tests/js failed; the loaders.gl and Chromium checks will not run" >&2
  fi
fi
