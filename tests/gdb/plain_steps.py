# Steps plain_draw (tests/gdb/plain_draw.cpp) in gdb and checks that the plain path goes through the
# stages in the pipeline's order, each in its own file (docs/DESIGN.md, "The plain path, for reading
# and stepping"):
#
#   gdb -batch -nx -x tests/gdb/plain_steps.py build/bin/plain_draw
#
# One breakpoint per stage, each taken at its first hit only; the order of the hits and the file of
# each stopping frame are checked, and the backtraces at the rasterizer's edge function and at the
# blend must name the fill path's and the stages' files. Exits gdb with status 0 when all holds, 1
# with the reason otherwise.
import gdb

# (stage, breakpoint location, file the stopping frame must be in), in the pipeline's order.
STAGES = [
    ("input assembler", "raster::assemble", "src/input_assembler.cpp"),
    ("vertex shader", "(anonymous namespace)::VsPlain::operator()", "plain_draw.cpp"),
    ("geometry shader", "(anonymous namespace)::GsPlain::operator()", "plain_draw.cpp"),
    ("clipper", "raster::outcode", "stages/4_clipper.hpp"),
    ("setup", "raster::setupTriangle", "stages/5_setup.hpp"),
    ("rasterizer edge function", "raster::edgeAt", "stages/7_rasterizer.hpp"),
    ("pixel shader", "(anonymous namespace)::PsPlain::operator()", "plain_draw.cpp"),
    ("depth test", "raster::depthPasses", "stages/9_output_merger.hpp"),
    ("blend", "raster::mergeFragment<float>", "stages/9_output_merger.hpp"),
]
# Files each backtrace must name (its frames' source files, innermost first).
BACKTRACE_FILES = {
    "vertex shader": ["stages/2_vertex_shader.hpp", "pipeline_impl.hpp"],
    "geometry shader": ["stages/3_geometry_shader.hpp", "pipeline_impl.hpp"],
    "clipper": ["bin_primitives.hpp", "pipeline_impl.hpp"],
    "rasterizer edge function": ["stages/7_rasterizer.hpp", "fill/quads.hpp", "fill/fill_tile.hpp", "pipeline_impl.hpp"],
    "pixel shader": ["stages/8_pixel_shader.hpp", "fill/tile.hpp", "fill/quads.hpp"],
    "depth test": ["fastpath/merge_policy.hpp", "fill/tile.hpp", "fill/quads.hpp"],
    "blend": ["stages/9_output_merger.hpp", "fastpath/merge_policy.hpp", "fill/tile.hpp", "fill/quads.hpp",
              "fill/fill_tile.hpp"],
}


def frame_files():
    files = []
    frame = gdb.newest_frame()
    while frame is not None:
        sal = frame.find_sal()
        if sal.symtab is not None:
            files.append(sal.symtab.filename)
        frame = frame.older()
    return files


def fail(message):
    print("plain_steps: FAIL: " + message)
    gdb.execute("kill", to_string=True)
    gdb.execute("quit 1")


gdb.execute("set pagination off")
gdb.execute("set confirm off")
breakpoints = {}
for stage, location, _ in STAGES:
    bp = gdb.Breakpoint(location, internal=False)
    if bp.pending or not bp.locations:
        fail("no code for the %s at '%s' (built with -O0 -g?)" % (stage, location))
    breakpoints[bp.number] = stage

hits = []
gdb.execute("run", to_string=True)
while True:
    try:
        frame = gdb.selected_frame()
    except gdb.error:
        break  # the program has exited
    stopped = [bp for bp in gdb.breakpoints() if bp.is_valid() and bp.hit_count > 0 and bp.number in breakpoints]
    if not stopped:
        gdb.execute("continue", to_string=True)
        continue
    for bp in stopped:
        stage = breakpoints.pop(bp.number)
        sal = frame.find_sal()
        here = sal.symtab.filename if sal.symtab else "?"
        files = frame_files()
        hits.append(stage)
        print("plain_steps: %-25s %s:%d" % (stage, here, sal.line))
        expected = dict((s, f) for s, _, f in STAGES)[stage]
        if not here.endswith(expected):
            fail("the %s stopped in %s, not in %s" % (stage, here, expected))
        for want in BACKTRACE_FILES.get(stage, []):
            if not any(f.endswith(want) for f in files):
                fail("the backtrace at the %s names no %s:\n  %s" % (stage, want, "\n  ".join(files)))
        bp.delete()
    if not breakpoints:
        break
    gdb.execute("continue", to_string=True)

order = [s for s, _, _ in STAGES]
if hits != order:
    fail("stages hit in the order %s, not %s" % (hits, order))
print("plain_steps: %d stages in order, each in its own file" % len(hits))
gdb.execute("kill", to_string=True)
gdb.execute("quit 0")
