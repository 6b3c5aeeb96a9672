#!/usr/bin/env bash
# Gradescope's setup.sh for `raster grade` (docs/GRADING.md, "Grading on Gradescope"). Gradescope runs
# it once, as root, when it builds the autograder's image, with the zip unpacked in /autograder/source:
#  1. installs from the distribution's packages what building the grader needs (the part of .ci/setup's
#     list that build/bin/raster needs; tests/gradescope_test.py checks that it stays a part of it);
#  2. builds the grader, build/bin/raster and the lab runner library it links submissions with, in
#     Release for x86-64-v3 processors (AVX2, FMA: every x86-64 server since about 2015), not
#     -march=native: the image may run on another processor than the one that built it; the images
#     are the same bits either way (docs/GRADING.md). The x86-64 baseline (RASTER_AUTOGRADER_MARCH=
#     empty) runs anywhere but compiles the pipeline's vector code ten times slower; run_autograder
#     refuses, naming the missing features, to grade on a processor the image was not built for;
#  3. locks the solutions away from the submission, which runs as `nobody` under a root grader:
#     solutions/ and the build's files that hold the solutions compiled (bin/, labs/) become root's
#     alone, and it checks, as nobody, that the rest of what a submission's build reads is readable.
# Environment (tests and local runs; Gradescope sets none of it):
#   AUTOGRADER_ROOT               the folder laid out like /autograder (default /autograder)
#   RASTER_AUTOGRADER_PREBUILT    a build folder of raster (bin/raster, bin/grade_toolchain.json): use it
#                                 as build/, install nothing and compile nothing (tests/gradescope_test.py)
#   RASTER_AUTOGRADER_MARCH       -march= of the build (default x86-64-v3; set and empty: the compiler's
#                                 x86-64 baseline)
#   RASTER_AUTOGRADER_BUILD_JOBS  compiles at once (default: the processors there are)
set -euo pipefail
root=${AUTOGRADER_ROOT:-/autograder}
source_dir=$root/source
build=$source_dir/build
prebuilt=${RASTER_AUTOGRADER_PREBUILT:-}
say() { echo "setup.sh: $*"; }
fail() {
  echo "setup.sh: $*" >&2
  exit 1
}
[[ -f $source_dir/CMakeLists.txt && -d $source_dir/solutions && -d $source_dir/labs ]] ||
  fail "$source_dir holds no raster source tree (CMakeLists.txt, labs/, solutions/): is AUTOGRADER_ROOT ($root) right?"

# $1 >= $2, as version numbers.
version_at_least() { printf '%s\n%s\n' "$2" "$1" | sort -V -C; }

install_packages() {
  # The compiler, CMake and Ninja; python3 runs run_autograder; the libraries build/bin/raster links:
  # GLM and stb (the library), SDL2 (the viewer) and Google Benchmark (raster bench) are part of the one
  # program, CLI11 its command line, nlohmann's JSON the trace and the grader's files, NanoVDB the
  # voxel grids' .nvdb files.
  local packages=(build-essential cmake ninja-build python3 libglm-dev libstb-dev libsdl2-dev
    libbenchmark-dev libcli11-dev nlohmann-json3-dev libnanovdb-dev)
  local missing=() p
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    say "installing ${missing[*]}"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
  # raster needs CMake 3.25 and GCC 12 (C++20). Debian 12 and Ubuntu 24.04 have them; Ubuntu 22.04
  # (Gradescope's default base image in 2025) has CMake 3.22 and GCC 11: then GCC 12 from its packages
  # and CMake from PyPI.
  local cmake_version
  cmake_version=$(cmake --version | head -n 1 | awk '{print $3}')
  if ! version_at_least "$cmake_version" 3.25; then
    say "CMake $cmake_version is older than the 3.25 raster needs: installing CMake from PyPI"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-pip
    python3 -m pip install --quiet 'cmake>=3.25,<4'
    hash -r
  fi
  if ! version_at_least "$(g++ -dumpfullversion)" 12; then
    say "g++ $(g++ -dumpfullversion) is older than the 12 raster needs: installing g++-12"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends g++-12
    export CXX=g++-12
  fi
}

build_grader() {
  # -Wno-psabi: without AVX, GCC notes at each inline function of raster's headers that takes or
  # returns a 32-byte vector that such vectors are passed differently with AVX (they are inlined: no
  # call crosses an ABI boundary). The submission's compile takes these flags too (grade_toolchain.json),
  # and its log is what a student reads when it fails.
  local cxx_flags="-Wno-psabi"
  local march=${RASTER_AUTOGRADER_MARCH-x86-64-v3}
  [[ -z $march ]] || cxx_flags+=" -march=$march"
  local jobs=${RASTER_AUTOGRADER_BUILD_JOBS:-$(nproc)}
  cmake -S "$source_dir" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRASTER_NATIVE=OFF \
    -DRASTER_BUILD_TESTS=OFF -DRASTER_FUZZ_REPLAY=OFF "-DCMAKE_CXX_FLAGS=$cxx_flags"
  cmake --build "$build" --target raster_tool -j "$jobs"
  echo "$march" > "$build/autograder_march.txt"  # run_autograder checks the processor against it
}

# What the grader runs as when it is root (raster/tools/grade/sandbox.hpp).
as_nobody() { setpriv --reuid=nobody --regid="$(id -g nobody)" --clear-groups "$@"; }

# solutions/ (and the solutions compiled, in a build of our own) for root alone; then, as nobody, the
# solution unreadable and every file a submission's compile and link name readable.
lock_solutions() {
  chmod -R a+rX "$source_dir/raster" "$source_dir/labs"
  chmod -R go-rwx "$source_dir/solutions"
  [[ -n $prebuilt ]] || chmod -R go-rwx "$build/bin" "$build/labs"
  [[ $(id -u) == 0 ]] || return 0
  local solution
  solution=$(find "$source_dir/solutions" -name '*.cpp' -print -quit)
  if [[ -n $solution ]] && as_nobody test -r "$solution"; then
    fail "nobody can read $solution"
  fi
  local path
  while read -r path; do
    as_nobody test -r "$path" || fail "nobody cannot read $path, which a submission's build needs"
  done < <(python3 - "$build/bin/grade_toolchain.json" <<'EOF'
import json, os, sys
toolchain = json.load(open(sys.argv[1]))
for arg in toolchain["compile"] + toolchain["link"]:
    path = arg[2:] if arg.startswith("-I") else arg
    if os.path.isabs(path) and os.path.exists(path):
        print(path)
EOF
  )
}

if [[ -n $prebuilt ]]; then
  [[ -x $prebuilt/bin/raster && -f $prebuilt/bin/grade_toolchain.json ]] ||
    fail "RASTER_AUTOGRADER_PREBUILT=$prebuilt has no bin/raster and bin/grade_toolchain.json"
  say "using the grader built in $prebuilt (no packages, no compile)"
  rm -rf "$build"
  ln -s "$(cd "$prebuilt" && pwd)" "$build"
else
  start=$SECONDS
  install_packages
  build_grader
  say "built $build/bin/raster in $((SECONDS - start)) s"
fi
"$build/bin/raster" grade --help >/dev/null || fail "$build/bin/raster does not run"
lock_solutions
chmod a+rx "$source_dir/run_autograder"
[[ ! -f $root/run_autograder ]] || chmod a+rx "$root/run_autograder"
say "ready: run_autograder grades $root/submission into $root/results/results.json"
