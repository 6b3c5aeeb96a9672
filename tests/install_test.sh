#!/usr/bin/env bash
# cmake --install of an already built raster, and a project outside the tree built against it: the
# headers, libraster and raster-config.cmake land under the prefix; tests/install_consumer finds them
# with find_package(raster CONFIG REQUIRED), compiles README's "A first program" with the installed
# headers only (none of the source tree's) and draws the triangle with the right pixels; a version
# raster is not (1.0) is refused. Nothing of raster is rebuilt: the install copies what the build made.
#   bash tests/install_test.sh BUILD_DIR LIBRARY CONSUMER_DIR [CXX_COMPILER [CXX_FLAGS]]
# LIBRARY: the built libraster_lib.a (ctest passes $<TARGET_FILE:raster_lib>).
# CXX_FLAGS: what the library was compiled with that its exported target does not carry (a
# sanitizer build's -fsanitize=..., whose runtime the consumer must link too).
set -euo pipefail
build=$1
library=$2
consumer=$3
cxx=${4:-c++}
cxx_flags=${5:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
prefix=$tmp/prefix
source_dir=$(cd "$consumer/../.." && pwd)

# The install: what the build made, copied. A library older than its sources would be installed as it
# is, not rebuilt, so its time stamp must not change.
[[ -f $library ]] || fail "no library $library: build raster_lib first"
before=$(stat -c %Y "$library")
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1 || fail "cmake --install: $(cat "$tmp/install.log")"
[[ $(stat -c %Y "$library") == "$before" ]] || fail "cmake --install rebuilt $library"
for file in include/raster/pipeline.hpp include/raster/shaders/basic.hpp include/raster/image_compare.hpp \
  include/raster/scenes.hpp include/raster/trace_format.hpp lib/libraster_lecture.a lib/libraster_tooling.a \
  lib/libraster_lib.a lib/cmake/raster/raster-config.cmake lib/cmake/raster/raster-config-version.cmake \
  lib/cmake/raster/raster-targets.cmake; do
  [[ -f $prefix/$file ]] || fail "$file was not installed; installed: $(cd "$prefix" && find . -type f | head -20)"
done
cmp -s "$library" "$prefix/lib/libraster_lib.a" || fail "the installed library is not the built one"
# The exported target names no directory of the source tree or the build.
if grep -n -e "$source_dir/" -e "$(cd "$build" && pwd)/" "$prefix"/lib/cmake/raster/*.cmake >"$tmp/leak.txt"; then
  fail "the package configuration names the source or build tree: $(cat "$tmp/leak.txt")"
fi

# The consumer: configured and built against the prefix alone.
cmake -S "$consumer" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$tmp/configure.log" 2>&1 ||
  fail "configuring the consumer: $(cat "$tmp/configure.log")"
cmake --build "$tmp/build" -j1 >"$tmp/build.log" 2>&1 || fail "building the consumer: $(tail -40 "$tmp/build.log")"
grep -q -- "$prefix/include" "$tmp/build/compile_commands.json" ||
  fail "the consumer was not compiled with $prefix/include: $(cat "$tmp/build/compile_commands.json")"
if grep -q -- "$source_dir/raster" "$tmp/build/compile_commands.json"; then
  fail "the consumer was compiled with the source tree's headers: $(cat "$tmp/build/compile_commands.json")"
fi
grep -q -- "$prefix/lib/libraster_lib.a" "$tmp/build/CMakeFiles/first_program.dir/link.txt" ||
  fail "the consumer was not linked with the installed library: $(cat "$tmp/build/CMakeFiles/first_program.dir/link.txt")"
# raster::raster is the pipeline alone: a student's own project links neither the lecture nor the tooling.
if grep -q -e libraster_lecture -e libraster_tooling "$tmp/build/CMakeFiles/first_program.dir/link.txt"; then
  fail "raster::raster brought the lecture or the tooling: $(cat "$tmp/build/CMakeFiles/first_program.dir/link.txt")"
fi
for target in raster::lecture raster::tooling; do
  grep -q "add_library($target " "$prefix/lib/cmake/raster/raster-targets.cmake" || fail "$target is not exported"
done

# Its output: the triangle's centre orange (1, 0.5, 0, 1 → 255 128 0 255), outside it the clear colour.
"$tmp/build/first_program" >"$tmp/out.txt" 2>&1 || fail "the consumer failed: $(cat "$tmp/out.txt")"
printf 'pixel 128,128: 255 128 0 255\npixel 128,40: 0 0 0 255\npixel 128,200: 0 0 0 255\n' >"$tmp/expected.txt"
diff "$tmp/expected.txt" "$tmp/out.txt" >&2 || fail "the consumer's pixels are not the triangle's"

# The version file: raster 0.1 is not what a project asking for 1.0 gets.
mkdir "$tmp/version"
cat >"$tmp/version/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(raster_version_check LANGUAGES CXX)
find_package(raster 0.1 CONFIG REQUIRED)
message(STATUS "found raster ${raster_VERSION}")
find_package(raster 1.0 CONFIG QUIET)
if(raster_FOUND)
  message(FATAL_ERROR "raster ${raster_VERSION} was accepted for 1.0")
endif()
EOF
cmake -S "$tmp/version" -B "$tmp/version/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" \
  >"$tmp/version.log" 2>&1 || fail "the version check: $(cat "$tmp/version.log")"
grep -q 'found raster 0\.1\.0$' "$tmp/version.log" || fail "raster's version is not 0.1.0: $(cat "$tmp/version.log")"
echo "install: headers, libraster_lib.a and raster-config.cmake under a prefix; a project outside the tree"
echo "built against them draws README's triangle: $(tr '\n' ';' <"$tmp/out.txt")"
