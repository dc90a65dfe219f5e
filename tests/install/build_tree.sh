#!/usr/bin/env bash
# The C API used straight from a build tree, as docs/embedding.md's "From a build tree" does it: its pkg-config
# line, copied from the page and run word for word (from a scratch folder laid out like a checkout), compiles
# docs/examples/trace_octahedron.c; then the same program through find_package(megavox) with
# -Dmegavox_DIR=<build dir>. Each binary runs in an empty environment (no LD_LIBRARY_PATH), so the run paths
# alone must find libmegavox.so.
# Usage: build_tree.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
source "$src/tests/cli/common.sh"

# The page's commands, found by what they do rather than by line number.
page=$src/docs/embedding.md
compile=$(grep -E '^cc .*docs/examples/trace_octahedron\.c.*PKG_CONFIG_PATH=build pkg-config --cflags --libs megavox' \
  "$page" || true)
[[ $(echo "$compile" | grep -c .) == 1 ]] || fail "docs/embedding.md has no (or several) pkg-config line for the example: '$compile'"
run=$(grep -E '^\./trace_octahedron( |$)' "$page" | head -1 || true)
[[ -n "$run" ]] || fail "docs/embedding.md does not run ./trace_octahedron"
grep -Eq '^cmake -S docs/examples -B [^ ]+ -Dmegavox_DIR=' "$page" ||
  fail "docs/embedding.md's CMake line no longer configures docs/examples with megavox_DIR"

# The sanitizer build's library leaves the ASan runtime to the program (as in install_package.sh); its runs
# keep the sanitizer settings (suppressions of third-party leaks) in the otherwise empty environment.
keep=(PATH=/usr/bin:/bin)
if [[ $(nm -D --undefined-only "$build"/libmegavox.so) == *" __asan_"* ]]; then
  cc() { clang -fsanitize=address,undefined "$@" -fsanitize-link-c++-runtime -lstdc++; }
  export -f cc
  export CC=clang CFLAGS=-fsanitize=address,undefined LDFLAGS="-fsanitize=address,undefined -fsanitize-link-c++-runtime -lstdc++"
  for v in ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
    if [[ -n "${!v:-}" ]]; then keep+=("$v=${!v}"); fi
  done
fi

# pkg-config: a checkout's layout, the build tree under its usual name.
mkdir "$dir/checkout"
ln -s "$src/docs" "$dir/checkout/docs"
ln -s "$build" "$dir/checkout/build"
cd "$dir/checkout"
bash -c "$compile" > "$dir/compile.log" 2>&1 || fail "docs/embedding.md's compile line failed: $compile
$(cat "$dir/compile.log")"
out=$(env -i "${keep[@]}" bash -c "$run" 2>&1) || fail "$run: $out"
hits=$(echo "$out" | awk '/^hits/ {print $2}')
[[ -n "$hits" && $hits -gt 96 && $hits -lt 192 ]] || fail "$run: $out"

# CMake: the example's own project, configured against the build tree.
cmake -S "$src/docs/examples" -B "$dir/cmake" -Dmegavox_DIR="$build" > "$dir/configure.log" 2>&1 ||
  fail "configure with megavox_DIR=$build: $(cat "$dir/configure.log")"
cmake --build "$dir/cmake" > "$dir/build.log" 2>&1 || fail "build: $(cat "$dir/build.log")"
out2=$(env -i "${keep[@]}" "$dir/cmake/trace_octahedron" 2>&1) || fail "the CMake build: $out2"
[[ $(echo "$out2" | awk '/^hits/ {print $2}') == "$hits" ]] || fail "the CMake build: $out2 (pkg-config's: $hits)"
echo "from the build tree, by pkg-config and by CMake: $hits of 256 rays hit"
