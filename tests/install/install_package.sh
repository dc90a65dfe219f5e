#!/usr/bin/env bash
# `cmake --install` into a scratch prefix, then what a user does with it: the library exports only mv*
# symbols under a versioned SONAME and needs no baseline; the tree is moved (relocatable), an outside CMake
# project finds it with find_package(megavox) and traces rays into a .mvx the installed CLI builds; the same
# program builds again from pkg-config's flags alone.
# Usage: install_package.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$2
source "$src/tests/cli/common.sh"

cmake --install "$build" --prefix "$dir/first" > /dev/null
mv "$dir/first" "$dir/prefix"  # relocatable: nothing may point back at the first place
prefix=$dir/prefix
lib=$(ls "$prefix"/lib*/libmegavox.so.*.*.* 2>/dev/null | head -1)
[[ -n "$lib" ]] || fail "no libmegavox.so.X.Y.Z under $prefix: $(find "$prefix" -type f)"
soname=$(objdump -p "$lib" | awk '/SONAME/ {print $2}')
[[ $soname =~ ^libmegavox\.so\.[0-9]+\.[0-9]+$ ]] || fail "SONAME '$soname'"
[[ -e "$(dirname "$lib")/$soname" && -e "$(dirname "$lib")/libmegavox.so" ]] || fail "the SONAME and dev links"
others=$(nm -D --defined-only "$lib" | awk '{print $NF}' | grep -v '^mv[A-Z]' | grep -v '^MEGAVOX_' || true)
[[ -z "$others" ]] || fail "exports beyond mv*: $(echo "$others" | head -5)"
nm -D --defined-only "$lib" | grep -q ' mvTraceRays' || fail "mvTraceRays not exported"
if objdump -p "$lib" | grep NEEDED | grep -Eiq 'embree|boost|hwy|gomp'; then fail "a baseline library is linked"; fi
for f in include/megavox/megavox.h include/megavox/megavox.hpp include/megavox/version.h bin/megavox; do
  [[ -e "$prefix/$f" ]] || fail "$f not installed"
done
[[ ! -e "$prefix/include/megavox/trace.h" ]] || fail "the internal C++ headers are installed"
grep -rq "$dir/first" "$prefix" && fail "the tree names where it was installed first"

write_tetra_ply "$dir/tetra.ply"
"$prefix/bin/megavox" build "$dir/tetra.ply" --resolution 32 -o "$dir/tetra.mvx" > /dev/null

# The sanitizer build's library leaves the ASan runtime to the program, so its consumers build the same way.
sanitize=()
sanitize_link=()
if [[ $(nm -D --undefined-only "$lib") == *" __asan_"* ]]; then  # (grep -q would end nm early under pipefail)
  export CC=clang
  sanitize=(-fsanitize=address,undefined)
  sanitize_link=(-fsanitize-link-c++-runtime -lstdc++)  # the library's C++ checks (UBSan's vptr) need these
fi
cmake -S "$src/tests/install/consumer" -B "$dir/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_C_FLAGS="${sanitize[*]}" -DCMAKE_EXE_LINKER_FLAGS="${sanitize_link[*]}" > "$dir/configure.log" ||
  fail "configure: $(cat "$dir/configure.log")"
cmake --build "$dir/consumer" > "$dir/build.log" || fail "build: $(cat "$dir/build.log")"
out=$("$dir/consumer/trace_mvx" "$dir/tetra.mvx") || fail "trace_mvx: $out"
hits=$(echo "$out" | awk '/^hits/ {print $2}')
[[ -n "$hits" && $hits -gt 64 && $hits -lt 256 ]] || fail "trace_mvx: $out"

pcdir=$(dirname "$(ls "$prefix"/lib*/pkgconfig/megavox.pc)")
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs megavox)
"${CC:-cc}" -std=c99 "${sanitize[@]}" -o "$dir/trace_pc" "$src/tests/install/consumer/trace_mvx.c" $flags -lm \
  "${sanitize_link[@]}"
out2=$(LD_LIBRARY_PATH=$(dirname "$lib") "$dir/trace_pc" "$dir/tetra.mvx") || fail "pkg-config build: $out2"
[[ $(echo "$out2" | awk '/^hits/ {print $2}') == "$hits" ]] || fail "pkg-config build: $out2"
# The Python module, where the build made one: installed beside the library, it imports from a clean
# environment and traces the same hits as the C program (the same 256 rays: tests/install/consumer/trace_mvx.c).
if compgen -G "$build/python/megavox/_megavox*.so" > /dev/null; then
  module=$(ls "$prefix"/lib/python3*/dist-packages/megavox/_megavox*.so 2>/dev/null | head -1)
  [[ -n "$module" ]] || fail "the Python module is not installed under $prefix/lib/python3*/dist-packages"
  site=$(dirname "$(dirname "$module")")
  for f in __init__.py __init__.pyi points.py mask.py py.typed; do
    [[ -e "$site/megavox/$f" ]] || fail "megavox/$f not installed in $site"
  done
  py=$(env -i PATH=/usr/bin:/bin PYTHONPATH="$site" /usr/bin/python3 -c "$(cat "$src/tests/install/trace_mvx.py")" \
    "$dir/tetra.mvx" 2>&1) || fail "python: $py"
  [[ $(echo "$py" | awk '/^hits/ {print $2}') == "$hits" ]] || fail "python: $py (the C program: $hits hits)"
fi
echo "installed, found by CMake and pkg-config, $hits of 256 rays hit"
