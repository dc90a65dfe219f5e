#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (every kernel test on every OpenCL and Vulkan device found).
# Usage: scripts/test.sh             the Release build in build/
#        scripts/test.sh --sanitize  the same suite built with clang, ASan and UBSan in build-sanitize/ (slow:
#                                    run it niced). Faults inside third-party libraries (PoCL and its LLVM,
#                                    Mesa, the ICD loaders) are suppressed by the narrow, commented lists in
#                                    scripts/sanitize/; megavox's own code is never listed there.
#        scripts/test.sh --sanitize=thread  the C API and service tests built with clang and TSan in build-tsan/
#                                    (the handles' lifetimes and the service's threads). TBB runs its loops on
#                                    the calling thread there (runtime/device.cpp); the drivers' own threads,
#                                    which TSan cannot see into, are named in scripts/sanitize/tsan.supp.
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "")
    scripts/setup.sh
    scripts/build.sh -DMEGAVOX_BASELINES=OFF   # the test path provably needs no baseline library
    cd build
    ctest --output-on-failure --parallel "$(nproc)"
    ;;
  --sanitize)
    scripts/setup.sh --fuzz   # clang and its sanitizer runtimes
    generator=()
    [[ ! -f build-sanitize/CMakeCache.txt ]] && command -v ninja >/dev/null && generator=(-G Ninja)
    CC=clang CXX=clang++ cmake -S . -B build-sanitize "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DMEGAVOX_BASELINES=OFF -DMEGAVOX_SANITIZE=ON >/dev/null
    supp=$PWD/scripts/sanitize
    # LSan runs at exit (leaks), ASan at every access; a UBSan report aborts the test (-fno-sanitize-recover).
    # Set before the build: its test discovery runs the test binary, which lists the devices.
    export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:${ASAN_OPTIONS:-}"  # tests/sanitizer_new.cpp
    export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
    cmake --build build-sanitize --parallel "$(nproc)"
    cd build-sanitize
    ctest --output-on-failure --parallel "$(nproc)" --timeout 1800
    ;;
  --sanitize=thread)
    scripts/setup.sh --fuzz
    generator=()
    [[ ! -f build-tsan/CMakeCache.txt ]] && command -v ninja >/dev/null && generator=(-G Ninja)
    CC=clang CXX=clang++ cmake -S . -B build-tsan "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DMEGAVOX_BASELINES=OFF -DMEGAVOX_SANITIZE=thread >/dev/null
    export TSAN_OPTIONS="suppressions=$PWD/scripts/sanitize/tsan.supp:halt_on_error=1:second_deadlock_stack=1:${TSAN_OPTIONS:-}"
    cmake --build build-tsan --parallel "$(nproc)" --target megavox megavox_tests megavox_c99_consumer serve_load serve_request_tests serve_pool_tests
    cd build-tsan
    ctest --output-on-failure --parallel "$(nproc)" --timeout 1800 -R 'CApi|Serve'
    ;;
  *) echo "usage: scripts/test.sh [--sanitize | --sanitize=thread]" >&2; exit 2 ;;
esac
