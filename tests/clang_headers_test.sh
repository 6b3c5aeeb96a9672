#!/usr/bin/env bash
# Every header of the library compiles alone (it includes what it uses), with clang 14, and without a
# warning (-Wall -Wextra -Werror): the second compiler CI holds the project's own code to, beside the
# GCC build whose output .ci/build checks for warnings. Each header is compiled at -O0 from a one-line
# file of its own in WORK-DIR (a header's templates are not instantiated, so the object holds next to
# nothing, and the time is the front end's: about 1.4 s a header), through LAUNCHER where the build
# compiles through one (ccache, `|` between its words): ccache caches an object, never a failed
# compile, and hashes every header the file includes, so a header that changed, or includes one that
# did, is compiled again and only an unchanged pass is served from the cache.
#     clang_headers_test.sh <source-dir> [clang++] [work-dir] [launcher]
set -euo pipefail
source_dir=$(cd "$1" && pwd)
clang=${2:-clang++}
if ! command -v "$clang" >/dev/null; then
  echo "clang_headers: no $clang on this machine (.ci/setup tests installs Debian's clang)" >&2
  exit 1
fi
cd "$source_dir"
mapfile -t includes < <(find raster -path '*/include' -type d | sort)
mapfile -t headers < <(for d in "${includes[@]}"; do find "$d" -name '*.hpp' -printf "%P\n"; done | sort)
((${#headers[@]} > 20)) || { echo "clang_headers: found only ${#headers[@]} headers under ${includes[*]}" >&2; exit 1; }
work=${3:-$(mktemp -d)}
launcher=()
[[ -n ${4:-} ]] && IFS='|' read -r -a launcher <<< "$4"
mkdir -p "$work"
flags=(-std=c++20 -O0 -march=native -ffp-contract=off -Wall -Wextra -Wno-missing-field-initializers
       -Werror -isystem /usr/include/stb)
for d in "${includes[@]}"; do flags+=(-I"$source_dir/$d"); done
check() {  # one header, alone
  local file="$work/${1//\//_}.cpp" text
  text=$(printf '#include "%s"' "$1")
  # Written only when it differs, so that the file is never newer than the cache's record of it.
  [[ -f $file && $(<"$file") == "$text" ]] || printf '%s\n' "$text" >"$file"
  if ! out=$(cd "$work" && "${launcher[@]}" "$clang" "${flags[@]}" -c "$file" -o "${file%.cpp}.o" 2>&1); then
    printf '%s:\n%s\n' "$1" "$out"
    return 1
  fi
}
failed=0
for h in "${headers[@]}"; do
  check "$h" || failed=$((failed + 1))
done
echo "clang_headers: ${#headers[@]} headers checked with $("$clang" --version | head -n 1), $failed failed"
((failed == 0))
