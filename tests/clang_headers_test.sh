#!/usr/bin/env bash
# Every header of the library compiles alone (it includes what it uses), with clang 14, and without a
# warning (-Wall -Wextra -Werror): the second compiler CI holds the project's own code to, beside the
# GCC build whose output .ci/build checks for warnings. Syntax only (-fsyntax-only): clang's warnings
# are its front end's, so parsing each header finds them, at about half a second a header.
#     clang_headers_test.sh <source-dir> [clang++]
set -euo pipefail
source_dir=$1
clang=${2:-clang++}
if ! command -v "$clang" >/dev/null; then
  echo "clang_headers: no $clang on this machine (.ci/setup tests installs Debian's clang)" >&2
  exit 1
fi
cd "$source_dir"
mapfile -t includes < <(find raster -path '*/include' -type d | sort)
mapfile -t headers < <(for d in "${includes[@]}"; do find "$d" -name '*.hpp' -printf "%P\n"; done | sort)
((${#headers[@]} > 20)) || { echo "clang_headers: found only ${#headers[@]} headers under ${includes[*]}" >&2; exit 1; }
flags=(-x c++ -std=c++20 -fsyntax-only -march=native -ffp-contract=off -Wall -Wextra -Wno-missing-field-initializers
       -Werror -isystem /usr/include/stb)
for d in "${includes[@]}"; do flags+=(-I"$d"); done
check() {  # one header, alone
  if ! out=$(printf '#include "%s"\n' "$1" | "$clang" "${flags[@]}" - 2>&1); then
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
