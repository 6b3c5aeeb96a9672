#!/usr/bin/env python3
"""The library's rooms and the one way their arrows point (docs/DESIGN.md): the pipeline includes
nothing of the lecture or the tooling, and the lecture and the tooling include nothing of each other.

    rooms_test.py <source-dir> [--table]

Each room is a folder of raster/ (pipeline/, lecture/, tooling/, each with include/raster/ and src/)
and a CMake target (raster::raster, raster::lecture, raster::tooling). Every #include "raster/..."
or quoted local include of a library file is resolved to the file and its room; an include that
points backward fails, naming the file, the line and the header, and so does a library file left
outside the rooms. --table prints the files and lines per room and the include counts between rooms.
"""
import os
import re
import sys

ORDER = ["pipeline", "lecture", "tooling"]

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def library_files(raster_dir):
    """(path relative to raster/, room) of every C++ file of the library: a room is a folder."""
    for room in ORDER:
        for root, _, names in os.walk(os.path.join(raster_dir, room)):
            for name in sorted(names):
                if name.endswith((".hpp", ".cpp", ".h", ".inl")):
                    yield os.path.relpath(os.path.join(root, name), raster_dir), room


def resolve(raster_dir, rel, header):
    """The included file relative to raster/, or None when it is not the library's (std, glm, stb)."""
    candidates = [os.path.join(os.path.dirname(rel), header)]
    for room in ORDER:
        candidates += [os.path.join(room, "include", header), os.path.join(room, "src", header)]
    for c in candidates:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(raster_dir, c)):
            return c
    return None


def strays(raster_dir):
    """Library files outside the rooms (the flat raster/include and raster/src of old)."""
    out = []
    for top in ("include", "src"):
        for root, _, names in os.walk(os.path.join(raster_dir, top)):
            out += [os.path.relpath(os.path.join(root, n), raster_dir) for n in names]
    return out


def main(source_dir, table):
    raster_dir = os.path.join(source_dir, "raster")
    files = list(library_files(raster_dir))
    if len(files) < 50:
        print("rooms_test: only %d library files under %s" % (len(files), raster_dir))
        return 1
    room_of = dict(files)
    lines = {r: 0 for r in ORDER}
    counts = {r: 0 for r in ORDER}
    arrows = {}
    failures = ["raster/%s: a library file outside the rooms (raster/pipeline, lecture, tooling)" % f
                for f in strays(raster_dir)]
    for rel, room in files:
        with open(os.path.join(raster_dir, rel), encoding="utf-8") as f:
            text = f.read().splitlines()
        lines[room] += len(text)
        counts[room] += 1
        for number, line in enumerate(text, 1):
            m = INCLUDE.match(line)
            target = resolve(raster_dir, rel, m.group(1)) if m else None
            if target is None:
                continue
            to = room_of[target]
            if to != room:
                arrows[(room, to)] = arrows.get((room, to), 0) + 1
            if ORDER.index(to) > ORDER.index(room) or {room, to} == {"lecture", "tooling"}:
                failures.append("raster/%s:%d: the %s includes the %s's %s" % (rel, number, room, to, target))
    if table:
        for r in ORDER:
            print("%-8s %3d files %6d lines" % (r, counts[r], lines[r]))
        for (a, b), n in sorted(arrows.items()):
            print("%s -> %s: %d includes" % (a, b, n))
    for f in failures:
        print(f)
    print("rooms_test: %d files in %d rooms, %d failures" % (len(files), len(ORDER), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], "--table" in sys.argv[2:]))
