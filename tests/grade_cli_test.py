#!/usr/bin/env python3
"""raster grade end to end (docs/GRADING.md): grades one submission and checks its results.json.

    grade_cli_test.py RASTER SOURCE_DIR WORK_DIR CASE

CASE is `solutions` or `labs` (the source tree's own folders, graded on the real declarations: full
marks, and less than full marks on every lab), or the name of a folder of tests/grader/ (its patches
applied to today's solutions in a folder under WORK_DIR by grader_submissions.py, graded on the small
scenes of tests/grader/root, only the labs it holds (--lab): each must lose exactly the scenes its
defect reaches, with the diagnosis or the reason naming it), or `hostile`: the HOSTILE submissions
graded one after another as a class on one machine (check_hostile). Exit status 0 when every check
holds, 1 with what did not, 77 (skipped) when this machine has no file-system isolation, so that the
hostile submissions that read at run time must succeed (what held is printed).
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import grader_submissions

PARTICLES = {"small_start", "close_few"}  # tests/grader/root's billboards (input-layout, blending) scenes that draw particles
BILLBOARDS = {"small_start", "no_particles", "close_few"}
RASTERIZER = {"small_start", "turned", "tiny_image"}
# The rasterizer scenes where a pixel centre lies exactly on an edge (all but `turned`, whose camera
# turns every vertex off the pixel-centre lattice): where the opposite tie-break shows.
ON_EDGE = {"small_start", "tiny_image"}
RASTERIZER_STAGE = "rasterizer: "
# The diagnosis when the vertex buffer's data differ (particle-system's simulation), not the layout.
SIMULATED = "the vertex buffer holds another value (check what your code computes and uploads into it)"
# tests/grader/root's sprite-methods scenes: every one draws the firs; all but no_sprites the sprites.
SPRITE_METHODS = {"small_start", "no_sprites", "wide_fov"}
SPRITES = {"small_start", "wide_fov"}
# The hostile includes' refusal.
REFUSED = "compile refused: your file includes @REPO@/solutions/billboards/billboards.cpp, which is not part of the lab"
# tests/grader/root's stable-fog scenes: the default media, sigma 0 in green, a level camera (dy = 0 on the
# height fog's middle row), thin fog (sigma 1e-7) and a camera high above fog thinning upward, looking down.
STABLE_FOG = {"small_start", "green_clear", "level_view", "thin_fog", "high_above"}
# tests/grader/root's ray-marching scenes: the default march, six steps (mu*ds up to about 3), another light.
RAY_MARCHING = {"small_start", "few_steps", "other_light"}
NON_FINITE = ["pixel shader: ", "your pixel shader's output is NaN at (", "the scene's parameters:"]
# case: (lab, scenes lost, verdict of those, words that must be in their output)
CASES = {
    "wrong_blend": ("billboards", PARTICLES, "fail", ["blend: ", "your destination factor is Blend::InvSrcAlpha where the solution's is Blend::One"]),
    "depth_write_on": ("billboards", PARTICLES, "fail", ["depth test: ", "is depth write on?", "your depth write is on where the solution's is off"]),
    "offset_after_w": ("billboards", PARTICLES, "fail", ["geometry shader: ", "geometry shader output", "differs by"]),
    "gs_drops_corner": ("billboards", PARTICLES, "fail", ["geometry shader: ", "the geometry shader emitted 1 triangle (3 vertices)", "(solution: 2 triangles, 4 vertices)"]),
    "half_pixel_coverage": ("rasterizer", RASTERIZER, "fail", [RASTERIZER_STAGE, "is coverage tested at the pixel's centre"]),
    "bottom_right_rule": ("rasterizer", ON_EDGE, "fail", [RASTERIZER_STAGE, "lies exactly on the triangle's edge", "check the top-left rule"]),
    "crash": ("billboards", PARTICLES, "error", ["crashed: ", "SIGSEGV"]),
    "infinite_loop": ("billboards", PARTICLES, "error", ["timed out: "]),
    "unbounded_alloc": ("billboards", PARTICLES, "error", ["ran out of memory: "]),
    "fork_bomb": ("billboards", PARTICLES, "error", ["too many processes: "]),
    "snoop": ("billboards", set(), "pass", []),
    # A file that does not compile is named as such, its first error's file and line first.
    "compile_error": ("billboards", BILLBOARDS, "error", ["compile failed: billboards.cpp:29:", "error: ", "billboardSizes"]),
    "link_error": ("billboards", BILLBOARDS, "error", ["link failed: ", "undefined reference to", "additiveFireBlend"]),
    "alternative": (("billboards", "particle-system", "sprite-methods", "stable-fog"), set(), "pass", []),
    "age_offset": ("input-layout", PARTICLES, "fail", ["input assembler: ", "with AGE = ", "what the solution reads as LIFESPAN (is the element's AlignedByteOffset that field's offsetof?)"]),
    "colour_too_narrow": ("input-layout", PARTICLES, "fail", ["input assembler: ", "with COLOR = ", "the first 3 components and the defaults (0, 0, 0, 1) after them", "Format too narrow"]),
    "library_layout": ("input-layout", PARTICLES, "error", ["failed: ", "element COLOR0 (feeding `colour`) at byte 36", "stride of 48 bytes"]),
    "untransformed": ("input-layout", PARTICLES, "fail", ["vertex shader: ", "from the same input: its SV_Position is"]),
    # particle-system: the simulation's defects reach the pipeline as other vertex data.
    "gravity_up": ("particle-system", PARTICLES, "fail", ["input assembler: ", "with POSITION = ", SIMULATED]),
    "euler_step": ("particle-system", PARTICLES, "fail", ["input assembler: ", "with POSITION = ", SIMULATED]),
    "age_never_reset": ("particle-system", PARTICLES, "fail", ["input assembler: ", "with POSITION = ", SIMULATED]),
    "colour_reversed": ("particle-system", PARTICLES, "fail", ["input assembler: ", "with SIZE = ", SIMULATED]),
    "disc_crowded": ("particle-system", PARTICLES, "fail", ["input assembler: ", "with POSITION = ", SIMULATED]),
    "blend_alternative": ("blending", set(), "pass", []),
    "blend_depth_write": ("blending", PARTICLES, "fail", ["depth test: ", "is depth write on?", "your depth write is on where the solution's is off"]),
    "over_dest_one": ("blending", PARTICLES, "fail", ["blend: ", "your destination factor is Blend::One where the solution's is Blend::InvSrcAlpha"]),
    "front_to_back": ("blending", PARTICLES, "fail", ["blend: ", "fragments in another order: yours from depth", "(near to far), the solution's", "(far to near)", "yours is the solution's order reversed"]),
    # The sorted panel's particles aligned by their vertices (another order is not other geometry).
    "unsorted_key": ("blending", PARTICLES, "fail", ["blend: ", "fragments in another order", "yours takes them in the vertex buffer's order, as stored"]),
    "half_done_blending": ("blending", PARTICLES, "fail", ["blend: ", "your blending is off where the solution's is on"]),
    "slide_comparator": ("blending", PARTICLES, "error", ["failed: ", "drawnBefore is not a strict weak ordering", "ties must be transitive"]),
    # sprite-methods: a wrong method or fir moves the corners its vertex or geometry shader outputs.
    "inverse_transpose": ("sprite-methods", SPRITES, "fail", ["vertex shader: ", "from the same input: its SV_Position is"]),
    "corners_in_world": ("sprite-methods", SPRITES, "fail", ["vertex shader: ", "from the same input: its SV_Position is"]),
    "gs_unscaled": ("sprite-methods", SPRITES, "fail", ["geometry shader: ", "geometry shader output", "differs by"]),
    "tree_faces_eye": ("sprite-methods", SPRITE_METHODS, "fail", ["vertex shader: ", "from the same input: its SV_Position is"]),
    "tree_eye_as_direction": ("sprite-methods", SPRITE_METHODS, "fail", ["vertex shader: ", "from the same input: its SV_Position is"]),
    # Hostile (check_hostile): each reaches for the solution, another submission or the reports, and
    # earns what its own code does, nothing; @REPO@ the source tree, @CLASS@ the class's folder.
    "include_absolute": ("billboards", BILLBOARDS, "error", [REFUSED]),
    "include_climbing": ("billboards", BILLBOARDS, "error", [REFUSED]),
    "include_link": ("billboards", BILLBOARDS, "error", ["answer.cpp: No such file or directory"]),
    "linked_lab": ("billboards", BILLBOARDS, "error", ["billboards/billboards.cpp is a symbolic link (to @REPO@/solutions/billboards/billboards.cpp), which the grader does not follow"]),
    "print_solution": ("billboards", BILLBOARDS, "error", ["cannot read @REPO@/solutions/billboards/billboards.cpp: ", "cannot read @REPO@/solutions/billboards/grading.json: "]),
    "read_other": ("billboards", BILLBOARDS, "error", ["cannot read @CLASS@/submissions/bystander/billboards/billboards.cpp: "]),
    "write_report": ("billboards", BILLBOARDS, "error", ["cannot write @CLASS@/reports/write_report/forged.txt: ", "cannot write @CLASS@/reports/bystander/results.json: "]),
    "draw_expected": ("billboards", BILLBOARDS, "error", ["found no expected image in @CLASS@/reports: "]),
    # stable-fog: each naive form loses the hidden medium it cannot take, named as a NaN where it is one.
    "fog_direct": ("stable-fog", {"green_clear"}, "fail", NON_FINITE + ["--sigma 0.0500000007,0,0.0700000003"]),
    "fog_sigma_floor": ("stable-fog", {"thin_fog"}, "fail", ["pixel shader: ", "your pixel shader returned"]),
    "slide_exponent": ("stable-fog", STABLE_FOG, "fail", ["pixel shader: "]),
    "no_sky": ("stable-fog", STABLE_FOG - {"high_above"}, "fail", ["pixel shader: ", "your pixel shader returned (0.000, 0.000, 0.000, 1.000)"]),
    "naive_height": ("stable-fog", {"level_view", "high_above"}, "fail", NON_FINITE + ["--camera "]),
    # ray-marching: Euler for the exponential step loses the few-step scene and the brighter other light; the phase function's and the
    # shadow ray's defects every scene.
    "march_euler": ("ray-marching", {"few_steps", "other_light"}, "fail", ["pixel shader: "]),
    "hg_slide_exponent": ("ray-marching", RAY_MARCHING, "fail", ["pixel shader: "]),
    "hg_sign_g": ("ray-marching", RAY_MARCHING, "fail", ["pixel shader: "]),
    "shadow_ignores_medium": ("ray-marching", RAY_MARCHING, "fail", ["pixel shader: "]),
    "march_alternative": ("ray-marching", set(), "pass", []),
}
# The hostile submissions, graded by the `hostile` case; the first four are stopped at build time,
# without any isolation too (the compiler's list of what it read; only the lab's file is copied; a
# link is not followed), the rest at run time only by the file-system isolation.
HOSTILE = ["include_absolute", "include_climbing", "include_link", "linked_lab", "print_solution", "read_other",
           "write_report", "draw_expected"]
BUILD_TIME = set(HOSTILE[:4])
# What a hostile submission prints where it succeeded: in no report.
SUCCESS_SIGNS = ["LEAKED", "FORGED"]
# The grader's files in a report folder: nothing else may be there after a grade.
REPORT_FILES = {"results.json", "junit.xml", "report.html"}
# Words a case's lost scenes must not say (a compile error is not the library's link).
ABSENT = {"compile_error": ["link failed"], "link_error": ["compile failed"]}
SCENES = {"billboards": BILLBOARDS, "input-layout": BILLBOARDS, "rasterizer": RASTERIZER,
          "particle-system": BILLBOARDS, "blending": BILLBOARDS, "sprite-methods": SPRITE_METHODS,
          "stable-fog": STABLE_FOG, "ray-marching": RAY_MARCHING}


def grade(raster, submission, out, extra, cwd):
    """Runs raster grade from `cwd` (the source tree: so that a submission that reached the grader's
    working directory, /proc/<grader>/cwd, would find solutions/ there; `snoop` tries)."""
    command = [raster, "grade", submission, "--out", out, "--jobs", "2"] + extra
    start = time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True, timeout=900, cwd=cwd)
    print(" ".join(command), f"({time.monotonic() - start:.1f} s)")
    print(done.stdout)
    if done.returncode != 0:
        print(done.stderr)
        raise SystemExit(f"raster grade exited with {done.returncode}, not 0")
    with open(os.path.join(out, "results.json"), encoding="utf-8") as f:
        return json.load(f)


def check_real(raster, source, out, case):
    # The untouched labs on their public scenes only (what a student's `--public` grades): each must
    # lose some there already, and the hidden scenes' renders and diagnoses would only add time.
    extra = ["--public"] if case == "labs" else []
    results = grade(raster, os.path.join(source, case), os.path.abspath(out), extra, source)
    errors = []
    labs = {}
    for t in results["tests"]:
        lab = t["name"].split(": ", 1)[0]
        score, top = labs.get(lab, (0, 0))
        labs[lab] = (score + t["score"], top + t["max_score"])
    if not labs:
        errors.append("no lab was graded")
    for lab, (score, top) in labs.items():
        if case == "solutions" and score != top:
            errors.append(f"{lab}: the solution scored {score} of {top}")
        if case == "labs" and score >= top:
            errors.append(f"{lab}: the untouched lab scored full marks ({score} of {top})")
    return errors


def check_case(raster, source, out, case, submission):
    lab, lost, verdict, words = CASES[case]
    labs = lab if isinstance(lab, tuple) else (lab,)  # a case may hold several labs' files
    root = os.path.join(source, "tests", "grader", "root")
    # The render limit: 4 s for infinite_loop, whose two looping scenes burn it whole; 30 s for
    # unbounded_alloc, so that on a loaded machine its 768 MiB run out before the clock does (it took
    # 8.8 s once with four builds sharing two cores); 8 s, ten times a scene's render, for the rest.
    seconds = {"infinite_loop": "4", "unbounded_alloc": "30"}.get(case, "8")
    extra = ["--grading-root", root, "--render-seconds", seconds, "--render-memory", "768"]
    for name in labs:
        extra += ["--lab", name]
    results = grade(raster, submission, os.path.abspath(out), extra, source)
    errors = scene_errors(results, labs, lost, verdict, words, ABSENT.get(case, []))
    if case == "snoop":
        for report in ("results.json", "junit.xml", "report.html"):
            with open(os.path.join(out, report), encoding="utf-8") as f:
                if "FORGED" in f.read():
                    errors.append(f"{report} holds the submission's forgery")
    return errors


def scene_errors(results, labs, lost, verdict, words, absent=()):
    """Each scene of `labs` graded; those `lost` with `verdict`, 0 points, `words` in their output and
    none of `absent`, the others full marks."""
    errors = []
    graded = {t["name"]: t for t in results["tests"]}
    expected = {f"{name}: {scene}" for name in labs for scene in SCENES[name]}
    if set(graded) != expected:
        errors.append(f"graded {sorted(graded)}, not the scenes of {', '.join(labs)} in tests/grader/root")
    for full_name, t in graded.items():
        name = full_name.split(": ", 1)[1]
        status = t["extra_data"]["verdict"]
        if name in lost:
            if t["score"] != 0 or status != verdict:
                errors.append(f"{full_name}: {status} with {t['score']} points, expected {verdict} with 0")
            for w in words:
                if w not in t["output"]:
                    errors.append(f"{full_name}: the output lacks {w!r}:\n{t['output']}")
            for w in absent:
                if w in t["output"]:
                    errors.append(f"{full_name}: the output says {w!r}:\n{t['output']}")
        elif t["score"] != t["max_score"]:
            errors.append(f"{full_name}: lost ({status}, {t['score']} of {t['max_score']}) but should not:\n{t['output']}")
    return errors


def snapshot(folder):
    """{path relative to `folder`: hash of its content, or "-> target" for a link} of every file below."""
    found = {}
    for parent, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(parent, name)
            if os.path.islink(path):
                found[os.path.relpath(path, folder)] = "-> " + os.readlink(path)
            elif os.path.isfile(path):
                with open(path, "rb") as f:
                    found[os.path.relpath(path, folder)] = hashlib.sha256(f.read()).hexdigest()
    return found


def open_to_all(folder):
    """Every folder and file below `folder` writable by all: as a grader that is not root leaves its
    reports to the submission's user (the same user), so that only the sandbox keeps one out."""
    for parent, _, files in os.walk(folder):
        os.chmod(parent, 0o777)
        for name in files:
            os.chmod(os.path.join(parent, name), 0o666)


def hostile_errors(raster, source, klass, name, places, extra):
    """Grades hostile submission `name` of the class and checks that it scored what its own code
    earns, that no report holds a sign of its success, and that nothing of the class but its own
    report changed, which holds the grader's files only."""
    out = os.path.join(klass, "reports", name)
    os.makedirs(out)
    open_to_all(os.path.join(klass, "reports"))
    before = snapshot(klass)
    results = grade(raster, os.path.join(klass, "submissions", name), out, extra, source)
    lab, lost, verdict, words = CASES[name]
    words = [grader_submissions.substitute(w, places) for w in words]
    errors = [f"{name}: {e}" for e in scene_errors(results, [lab], lost, verdict, words)]
    after = snapshot(klass)
    own = os.path.join("reports", name) + os.sep
    for path in sorted(set(before) | set(after)):
        if not path.startswith(own) and before.get(path) != after.get(path):
            errors.append(f"{name}: {path} changed while it was graded")
        if path.startswith(own) and os.path.basename(path) not in REPORT_FILES and not path.endswith(".png"):
            errors.append(f"{name}: its report folder holds {path}, which the grader did not write")
    # Signs of success in what changed while it was graded (its own report among them).
    for path in (p for p in after if p.startswith("reports" + os.sep) and before.get(p) != after[p]):
        with open(os.path.join(klass, path), "rb") as f:
            text = f.read()
        errors += [f"{name}: {path} holds {sign!r}" for sign in SUCCESS_SIGNS if sign.encode() in text]
    return errors


def check_hostile(raster, source, work):
    """The hostile submissions graded as a class is on one machine: in one folder (@CLASS@),
    submissions/<name>/ each and a bystander's (the solution: another student's work), graded one
    after another into reports/<name>/, the bystander first (its report holds the expected images).
    Returns the errors, the grader's line on its sandbox, and the errors of the submissions that only
    the file-system isolation stops where this machine has none (not counted)."""
    klass = os.path.join(work, "grade-hostile")
    shutil.rmtree(klass, ignore_errors=True)
    submissions, reports = os.path.join(klass, "submissions"), os.path.join(klass, "reports")
    places = {"@REPO@": os.path.realpath(source), "@CLASS@": klass}
    os.makedirs(os.path.join(submissions, "bystander", "billboards"))
    shutil.copyfile(os.path.join(source, "solutions", "billboards", "billboards.cpp"),
                    os.path.join(submissions, "bystander", "billboards", "billboards.cpp"))
    for name in HOSTILE:
        grader_submissions.materialise(source, name, submissions, places)
    root = os.path.join(source, "tests", "grader", "root")
    extra = ["--grading-root", root, "--lab", "billboards", "--render-seconds", "8", "--render-memory", "768"]
    results = grade(raster, os.path.join(submissions, "bystander"), os.path.join(reports, "bystander"), extra,
                    source)
    errors = [f"bystander: {e}" for e in scene_errors(results, ["billboards"], set(), "pass", [])]
    sandbox = results["output"].splitlines()[0]
    isolated = sandbox.startswith("sandbox: ") and "no file-system isolation" not in sandbox
    unprotected = []
    for name in HOSTILE:
        found = hostile_errors(raster, source, klass, name, places, extra)
        if isolated or name in BUILD_TIME:
            errors += found
        else:
            unprotected += found
    return errors, sandbox, unprotected


def main():
    raster, source, work, case = sys.argv[1:5]
    out = os.path.join(work, "grade-" + case)
    shutil.rmtree(out, ignore_errors=True)
    if case in ("solutions", "labs"):
        errors = check_real(raster, source, out, case)
    elif case == "hostile":
        errors, sandbox, unprotected = check_hostile(raster, source, os.path.abspath(work))
        if unprotected and not errors:
            print(f"SKIPPED: this machine has no file-system isolation ({sandbox}): the hostile submissions "
                  "that read or write at run time reached what they must not:\n" + "\n".join(unprotected))
            return 77
    else:
        with tempfile.TemporaryDirectory(prefix=f"grade-{case}-", dir=work) as made:
            try:
                submission = grader_submissions.materialise(source, case, made)  # made/<case>/<lab>/<lab>.cpp
            except grader_submissions.PatchError as e:
                print("FAILED:", e)
                return 1
            errors = check_case(raster, source, out, case, submission)
    for e in errors:
        print("FAILED:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
