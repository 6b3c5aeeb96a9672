#!/usr/bin/env python3
"""Intrinsics live only in the SIMD layer (docs/DESIGN.md): no C or C++ file of raster, the labs, the
solutions or the tests names a processor's intrinsic, its vector types or its headers, except
raster/pipeline/include/raster/simd/ (base.hpp's list: one header per instruction set), so that a stage
header reads as plain code calling named operations (raster/simd/ops.hpp).

    simd_intrinsics_test.py <source-dir>

Fails naming each file, line and name found; fails too if the layer itself holds no intrinsic (the
pattern would then be wrong) or if a header of the layer is missing.
"""
import os
import re
import sys

# x86: _mm_*, _mm256_*, _mm512_*, _MM_* macros, the __m128/__m256/__m512 types, the *intrin.h headers
# and GCC's __builtin_ia32_* builtins; Arm: arm_neon.h and its v…q_ operations' usual prefixes.
PATTERN = re.compile(
    r"\b(_mm(?:256|512)?_\w+|_MM_\w+|__m(?:64|128|256|512)[a-z]?|\w*intrin\.h|__builtin_ia32_\w+|arm_neon\.h"
    r"|v(?:ld1|st1|add|mul|fma)q_\w+)\b"
)
SOURCES = (".hpp", ".h", ".cpp", ".cc", ".c", ".inl")
ROOTS = ("raster", "labs", "solutions", "tests")
LAYER = os.path.join("raster", "pipeline", "include", "raster", "simd")
LAYER_HEADERS = ("base.hpp", "x86_128.hpp", "avx2.hpp", "avx512.hpp", "portable.hpp", "ops.hpp")


def sources(source_dir):
    for root in ROOTS:
        for path, dirs, files in os.walk(os.path.join(source_dir, root)):
            dirs[:] = sorted(d for d in dirs if not d.startswith((".", "build")))
            for name in sorted(files):
                if name.endswith(SOURCES):
                    yield os.path.join(path, name)


def main(source_dir):
    source_dir = os.path.realpath(source_dir)
    layer = os.path.join(source_dir, LAYER)
    missing = [h for h in LAYER_HEADERS if not os.path.isfile(os.path.join(layer, h))]
    if missing:
        print("simd_intrinsics_test: the SIMD layer lacks %s" % ", ".join(missing))
        return 1
    failed, in_layer, checked = 0, 0, 0
    for path in sources(source_dir):
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.read().split("\n")
        inside = path.startswith(layer + os.sep)
        checked += 0 if inside else 1
        for number, line in enumerate(lines, 1):
            for match in PATTERN.finditer(line):
                if inside:
                    in_layer += 1
                else:
                    print("simd_intrinsics_test: %s:%d uses %s outside the SIMD layer (%s)"
                          % (os.path.relpath(path, source_dir), number, match.group(1), LAYER))
                    failed = 1
    if in_layer == 0:
        print("simd_intrinsics_test: no intrinsic found in %s: the pattern is wrong" % LAYER)
        return 1
    print("simd_intrinsics_test: %d files outside the layer checked, %d intrinsics inside it"
          % (checked, in_layer))
    return failed


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
