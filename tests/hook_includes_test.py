#!/usr/bin/env python3
"""The draw's hooks come through one door (raster/draw_hooks.hpp, docs/DESIGN.md "Watching the
pipeline"): no stage header reaches the trace or the teaching pipeline through its includes, nor a
fast twin (fastpath/) or a fill loop (fill/), and the trace's interface reaches no stage.

    hook_includes_test.py <source-dir>

Follows the project's own #include "raster/..." lines from each header in a folder named `stages`
(wherever it lies under raster/pipeline/include) and from trace.hpp, and fails naming the header and the
chain of includes that reaches a forbidden one. Fails too if it finds no stage header or no
trace.hpp, so that a move cannot make it pass by checking nothing.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"(raster/[^"]+)"', re.M)
# What a stage must not reach, by file name.
HOOK_HEADERS = {"trace.hpp", "trace_recorder.hpp", "teaching_pipeline.hpp", "teaching_draw.hpp"}


def headers(include_root):
    """Every header under include_root, by its include path ("raster/...")."""
    found = {}
    for folder, _, files in os.walk(include_root):
        for name in files:
            if name.endswith(".hpp"):
                path = os.path.join(folder, name)
                found[os.path.relpath(path, include_root).replace(os.sep, "/")] = path
    return found


def chain_to(start, forbidden, files):
    """The include chain from start to the first header forbidden(name) accepts, or None."""
    seen, stack = {start}, [(start, [start])]
    while stack:
        current, chain = stack.pop()
        with open(files[current], encoding="utf-8") as f:
            text = f.read()
        for included in INCLUDE.findall(text):
            if included not in files or included in seen:
                continue
            if forbidden(included):
                return chain + [included]
            seen.add(included)
            stack.append((included, chain + [included]))
    return None


def main(source_dir):
    files = headers(os.path.join(source_dir, "raster", "pipeline", "include"))
    stages = sorted(h for h in files if "/stages/" in h)
    traces = sorted(h for h in files if os.path.basename(h) == "trace.hpp")
    if not stages or not traces:
        print("hook_includes_test: found %d stage headers and %d trace.hpp" % (len(stages), len(traces)))
        return 1
    failed = 0
    for stage in stages:
        chain = chain_to(stage, lambda h: os.path.basename(h) in HOOK_HEADERS, files)
        if chain:
            print("hook_includes_test: stage header %s reaches %s" % (stage, " -> ".join(chain)))
            failed += 1
    # The stages are the rules; their fast twins (fastpath/) and the loops that run them (fill/)
    # build on them, never the other way round.
    for stage in stages:
        chain = chain_to(stage, lambda h: h.startswith(("raster/fastpath/", "raster/fill/")), files)
        if chain:
            print("hook_includes_test: stage header %s reaches a fast path: %s" % (stage, " -> ".join(chain)))
            failed += 1
    for trace in traces:
        chain = chain_to(trace, lambda h: "/stages/" in h, files)
        if chain:
            print("hook_includes_test: %s reaches a stage: %s" % (trace, " -> ".join(chain)))
            failed += 1
    print("hook_includes_test: %d stage headers and %d trace interface checked, %d failures"
          % (len(stages), len(traces), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
