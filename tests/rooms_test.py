#!/usr/bin/env python3
"""The library's rooms and the one way their arrows point (docs/DESIGN.md): the pipeline includes
nothing of the lecture or the tooling, the lecture nothing of the tooling.

    rooms_test.py <source-dir> [--table]

Each file under raster/include/raster and raster/src belongs to one room, by the rules in ROOM_OF
(a path prefix or a file name, the first that matches). Every #include "raster/..." or quoted local
include of a file is resolved to its room; an include from a room to a later one in ORDER fails,
naming the file, the line and the header. PENDING lists the backward includes that still exist; the
test also fails when one of them is gone, so that the list only shrinks. --table prints the files and
lines per room and the include counts between rooms.
"""
import os
import re
import sys

ORDER = ["pipeline", "lecture", "tooling"]

# (path relative to raster/, room): the first rule whose path is a prefix of the file's wins.
ROOM_OF = [
    ("include/raster/scenes.hpp", "lecture"),
    ("include/raster/lab.hpp", "lecture"),
    ("include/raster/particles.hpp", "lecture"),
    ("include/raster/particle_sort.hpp", "lecture"),
    ("include/raster/particle_blending.hpp", "lecture"),
    ("include/raster/soft_particles.hpp", "lecture"),
    ("include/raster/shaders/", "lecture"),
    ("include/raster/media/", "lecture"),
    ("src/lecture/", "lecture"),
    ("src/scene", "lecture"),
    ("src/particle", "lecture"),
    ("src/soft_particles.cpp", "lecture"),
    ("src/smoke_shaders.hpp", "lecture"),
    ("src/voxel_grid.cpp", "lecture"),
    ("include/raster/image_compare.hpp", "tooling"),
    ("include/raster/image_io.hpp", "tooling"),
    ("src/image_compare.cpp", "tooling"),
    ("src/image_io.cpp", "tooling"),
    ("", "pipeline"),
]

# The trace's hooks in the draw (trace.hpp, trace_recorder.hpp's FragmentTracer, trace.cpp's Trace
# whose draws the pipeline fills) are the pipeline's; trace.cpp's text and JSON formatting would be
# the tooling's once it has a file of its own.
# Backward includes that exist today (file, header): RenderTarget::savePng, DepthTarget::savePng and
# the texture loader write and read images through image_io.
PENDING = {
    ("src/texture.cpp", "include/raster/image_io.hpp"),
    ("src/render_target.cpp", "include/raster/image_io.hpp"),
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def room_of(rel):
    for prefix, room in ROOM_OF:
        if rel.startswith(prefix):
            return room
    raise AssertionError(rel)


def library_files(raster_dir):
    for top in ("include", "src"):
        for root, _, names in os.walk(os.path.join(raster_dir, top)):
            for name in sorted(names):
                if name.endswith((".hpp", ".cpp", ".h", ".inl")):
                    yield os.path.relpath(os.path.join(root, name), raster_dir)


def resolve(raster_dir, rel, header):
    """The included file relative to raster/, or None when it is not the library's (std, glm, stb)."""
    candidates = [os.path.join(os.path.dirname(rel), header), os.path.join("include", header),
                  os.path.join("src", header)]
    for c in candidates:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(raster_dir, c)):
            return c
    return None


def main(source_dir, table):
    raster_dir = os.path.join(source_dir, "raster")
    files = list(library_files(raster_dir))
    if len(files) < 50:
        print("rooms_test: only %d library files under %s" % (len(files), raster_dir))
        return 1
    lines = {r: 0 for r in ORDER}
    counts = {r: 0 for r in ORDER}
    arrows = {}
    found_pending, failures = set(), []
    for rel in files:
        room = room_of(rel)
        with open(os.path.join(raster_dir, rel), encoding="utf-8") as f:
            text = f.read().splitlines()
        lines[room] += len(text)
        counts[room] += 1
        for number, line in enumerate(text, 1):
            m = INCLUDE.match(line)
            target = resolve(raster_dir, rel, m.group(1)) if m else None
            if target is None:
                continue
            to = room_of(target)
            if to != room:
                arrows[(room, to)] = arrows.get((room, to), 0) + 1
            if ORDER.index(to) > ORDER.index(room):
                if (rel, target) in PENDING:
                    found_pending.add((rel, target))
                else:
                    failures.append("raster/%s:%d: the %s includes the %s's %s" % (rel, number, room, to, target))
    for rel, target in sorted(PENDING - found_pending):
        failures.append("PENDING lists raster/%s including %s, which it no longer does: drop it" % (rel, target))
    if table:
        for r in ORDER:
            print("%-8s %3d files %6d lines" % (r, counts[r], lines[r]))
        for (a, b), n in sorted(arrows.items()):
            print("%s -> %s: %d includes%s" % (a, b, n, " (backward)" if ORDER.index(b) > ORDER.index(a) else ""))
    for f in failures:
        print(f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], "--table" in sys.argv[2:]))
