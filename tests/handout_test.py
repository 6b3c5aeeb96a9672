#!/usr/bin/env python3
"""The students' handout (docs/HANDOUT.md): made, checked for what it must not hold, and built and
run as a student would.

    handout_test.py leaks <source-dir> <build-dir> <cmake>
    handout_test.py build <source-dir> <build-dir> <cmake> <work-dir>

leaks: makes the handout (raster/tools/handout/handout.cmake with this build's raster) into
<build-dir>/handout, then fails on any relative link of its Markdown that does not resolve inside it
(docs_links_test.py's reading), on any file of solutions/, slides/ or tests/ in it, on any hidden
scene's name (solutions/<lab>/grading.json) or options, and on any line of a solution's answers (the
lines between `BEGIN LAB n` and `STAND-IN`, labs/generate.py) in any of its files — but those of the
library's own lecture code, listed exactly below (LIBRARY_ANSWERS), which are reported.

build: unpacks raster-course.tar.gz into <work-dir>, configures and builds its raster as the README's
commands do (.ci/build, without .ci/setup's packages; through ccache where this build used it), then
checks: `raster render <lab>` writes the lab's picture; `raster view <lab>`'s J compares with the
shipped image of the solution; `raster grade labs --public` grades every lab
below full marks as handed out and a solved lab (generate.py --solved) at full marks; every shipped
reference image is, byte for byte, what this build's `raster render <lab>@solution` writes at the
scene's options.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tarfile
import time

NAME = "raster-course"
FORBIDDEN_FOLDERS = ("solutions/", "slides/", "tests/")
# Answer lines that are code any C++ file may hold: not an answer.
GENERIC_LINES = {
    "for (int c = 0; c < 3; ++c) {",
    "RenderTargetBlendDesc& rt = blend.renderTarget[0];",
}
# Answer lines that the handout holds in the library's own lecture code, file by file, exactly: the
# lecture's scenes that the handout builds draw with them (docs/HANDOUT.md, "What the handout gives
# away"). A file's answer lines must be these and no others (a new one fails, and so does one that is
# no longer there, so that this list stays what the handout holds):
#   src/lecture/fire_shaders.hpp    the fire's gsBillboard and psFire: the billboards lab's LAB 1, LAB 2
#   src/lecture/sprite_shaders.hpp  the `sprites` and `forest` scenes: sprite-methods' LAB 2 and LAB 4
#   media/metaballs.hpp, march.hpp  the public media API (phase functions, density, march steps) that
#                                   the lecture's media scenes and its slides publish: ray-marching's
#                                   LAB 1 (the Euler step) and LAB 4 (the metaballs' density)
LIBRARY_ANSWERS = {
    "raster/lecture/src/lecture/fire_shaders.hpp": {
        "const float bx = billboardSize.x, by = billboardSize.y;",
        "stream.Append({c + glm::vec4(bx, by, 0, 0), {1, 0}});",
        "stream.Append({c + glm::vec4(bx, -by, 0, 0), {1, 1}});",
        "stream.Append({c + glm::vec4(-bx, by, 0, 0), {0, 0}});",
        "stream.Append({c + glm::vec4(-bx, -by, 0, 0), {0, 1}});",
        "return billboardTexture->Sample(sampler, in.tex);",
    },
    "raster/lecture/src/lecture/sprite_shaders.hpp": {
        "corner.x += in.size * in.corner.x;",
        "corner.y += in.size * in.corner.y;",
        "const glm::vec3 right = glm::normalize(side);",
    },
    "raster/lecture/include/raster/media/metaballs.hpp": {
        "const glm::vec3 v = x - ball.centre;",
        "const float u = glm::dot(v, v) / (ball.radius * ball.radius);",
    },
    "raster/lecture/include/raster/media/march.hpp": {
        "return L + ds * (q - mu * L);",
    },
}
MIN_ANSWER_LENGTH = 24  # shorter lines ("return x;", "}") are anyone's


def run(argv, **kw):
    started = time.monotonic()
    r = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if r.returncode != 0:
        print(r.stdout[-6000:])
        raise SystemExit("handout_test: failed (%d): %s" % (r.returncode, " ".join(argv)))
    return r.stdout, time.monotonic() - started


def make_handout(source, build, cmake):
    out = os.path.join(build, "handout")
    raster = os.path.join(build, "bin", "raster")
    said, seconds = run([cmake, "-DSOURCE_DIR=" + source, "-DOUTPUT_DIR=" + out, "-DRASTER=" + raster, "-P",
                         os.path.join(source, "raster", "tools", "handout", "handout.cmake")])
    print(said.strip(), "(%.1f s)" % seconds)
    return out


def handout_files(stage):
    for root, _, names in os.walk(stage):
        for name in names:
            path = os.path.join(root, name)
            yield os.path.relpath(path, stage), path


def answer_lines(source):
    """{line: solution file} of the solutions' answers, stripped, less comments, short and generic
    lines and lines the handed-out lab holds too (a signature the stand-in keeps)."""
    sys.path.insert(0, os.path.join(source, "labs"))
    import generate  # labs/generate.py: the markers' parser

    answers = {}
    solutions = os.path.join(source, "solutions")
    for lab in sorted(os.listdir(solutions)):
        solution = os.path.join(solutions, lab, lab + ".cpp")
        if not os.path.isfile(solution):
            continue
        with open(os.path.join(source, "labs", lab, lab + ".cpp")) as f:
            handed = {line.strip() for line in f}
        with open(solution) as f:
            parsed = generate.parse(f.read(), solution)
        for region in parsed.regions:
            if not region.kind.startswith("LAB"):
                continue
            for line in region.answer:
                text = line.strip()
                if (len(text) >= MIN_ANSWER_LENGTH and not text.startswith("//") and text not in handed
                        and text not in GENERIC_LINES):
                    answers.setdefault(text, os.path.relpath(solution, source))
    return answers


def hidden_scenes(source):
    """[(lab, scene)] of every solutions/<lab>/grading.json."""
    scenes = []
    solutions = os.path.join(source, "solutions")
    for lab in sorted(os.listdir(solutions)):
        path = os.path.join(solutions, lab, "grading.json")
        if os.path.isfile(path):
            with open(path) as f:
                scenes += [(lab, s) for s in json.load(f)["scenes"]]
    return scenes


def hidden_marks(lab, scene):
    """The regular expressions that would give a hidden scene away: its name as a name (a word of
    one word only where it is quoted or names a PNG: "turned" is English too) and its options, as
    JSON without white space (the camera alone too)."""
    name = re.escape(scene["name"])
    marks = [(r"[\"']%s[\"']" % name, False), (r"\b%s\.png\b" % name, False)]
    if "_" in scene["name"]:
        marks.append((r"\b%s\b" % name, False))
    compact = lambda value: (re.escape(json.dumps(value, separators=(",", ":"))), True)
    marks.append(compact(scene["options"]))
    if "camera" in scene["options"]:
        marks.append(compact(scene["options"]["camera"]))
    return marks


def check_leaks(source, stage):
    problems, reported = [], []
    answers = answer_lines(source)
    hidden = [(lab, s["name"], [(re.compile(m), squeeze) for m, squeeze in hidden_marks(lab, s)])
              for lab, s in hidden_scenes(source)]
    files = list(handout_files(stage))
    for rel, path in files:
        if rel.startswith(FORBIDDEN_FOLDERS):
            problems.append("%s: the handout holds a file of %s" % (rel, rel.split("/")[0]))
        if rel.endswith("grading.json") and not re.fullmatch(r"labs/[^/]+/grading\.json", rel):
            problems.append("%s: a grading declaration outside labs/<lab>/" % rel)
        if rel.endswith(".png"):
            continue
        with open(path, "rb") as f:
            text = f.read().decode("utf-8", "replace")
        squeezed = re.sub(r"\s+", "", text)
        for lab, name, marks in hidden:
            for mark, squeeze in marks:
                if mark.search(squeezed if squeeze else text):
                    problems.append("%s: names %s's hidden scene %s (%s)" % (rel, lab, name, mark.pattern))
        lines = {line.strip() for line in text.splitlines()}
        known = LIBRARY_ANSWERS.get(rel, set())
        for answer, solution in answers.items():
            if answer in lines:
                (reported if answer in known else problems).append(
                    "%s: holds an answer line of %s: %s" % (rel, solution, answer))
        for answer in sorted(known - (lines & set(answers))):
            problems.append("%s: LIBRARY_ANSWERS lists an answer line it no longer holds (or that is no "
                            "longer an answer): %s" % (rel, answer))
    for rel in sorted(set(LIBRARY_ANSWERS) - {rel for rel, _ in files}):
        problems.append("%s: listed in LIBRARY_ANSWERS, not in the handout" % rel)
    print("handout_test: %d files, %d answer lines and %d hidden scenes looked for" %
          (len(files), len(answers), len(hidden)))
    for line in reported:
        print("known (the library's lecture code): " + line)
    if len(answers) < 40 or len(hidden) < 10:
        problems.append("too few answer lines (%d) or hidden scenes (%d): is solutions/ there?" %
                        (len(answers), len(hidden)))
    return problems


def dead_links(stage):
    """Every relative link of the handout's Markdown that does not resolve inside the handout (a file
    or a heading it lacks), as docs_links_test.py finds them in the project."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import docs_links_test  # the project's link checker: the same reading of Markdown

    problems, checked = [], 0
    for rel, path in handout_files(stage):
        if not rel.endswith(".md"):
            continue
        checked += 1
        for line, target, why in docs_links_test.broken_links(path):
            problems.append("%s:%d: a link to %s: %s in the handout" % (rel, line, target, why))
    print("handout_test: the links of %d Markdown files looked at" % checked)
    if checked < 10:
        problems.append("only %d Markdown files in the handout" % checked)
    return problems


def leaks(source, build, cmake):
    out = make_handout(source, build, cmake)
    stage = os.path.join(out, NAME)
    with tarfile.open(os.path.join(out, NAME + ".tar.gz")) as archive:
        archived = {m.name for m in archive.getmembers() if m.isfile()}
    on_disk = {NAME + "/" + rel for rel, _ in handout_files(stage)}
    problems = check_leaks(source, stage) + dead_links(stage)
    if archived != on_disk:
        problems.append("the archive and the folder differ: %s" % sorted(archived ^ on_disk)[:10])
    for must in (".ci/setup", ".ci/build", "README.md", "CMakeLists.txt", "labs/billboards/billboards.cpp",
                 "labs/billboards/reference/billboards@solution.png", "labs/billboards/reference/start_camera.png"):
        if NAME + "/" + must not in archived:
            problems.append("the archive lacks " + must)
    with open(os.path.join(stage, "README.md")) as f:
        readme = f.read()
    commands = [line.strip() for line in readme.splitlines() if line.startswith("    ")][:2]
    if commands[:1] != ["bash .ci/setup && bash .ci/build && build/bin/raster render billboards --out-dir out --view"] \
            or commands[1:] != ["bash .ci/build && build/bin/raster grade labs --public"]:
        problems.append("the README does not open with the two commands: %s" % commands)
    for p in problems:
        print("FAIL " + p)
    print("handout_test: %s.tar.gz %d bytes, %d files" %
          (NAME, os.path.getsize(os.path.join(out, NAME + ".tar.gz")), len(archived)))
    return 1 if problems else 0


def render_flags(options):
    """raster render's flags for a grading scene's options (those the public scenes use)."""
    flags = []
    for key, value in options.items():
        if key in ("width", "height", "count", "seed", "time", "fov"):
            flags += ["--" + key, str(value)]
        else:
            raise SystemExit("handout_test: a public scene's option '%s' has no raster render flag here" % key)
    return flags


def check_references(build, stage, scratch):
    """Every reference image against this build's render of the solution: byte for byte."""
    raster = os.path.join(build, "bin", "raster")
    problems, checked = [], 0
    for lab in sorted(os.listdir(os.path.join(stage, "labs"))):
        reference = os.path.join(stage, "labs", lab, "reference")
        if not os.path.isdir(reference):
            continue
        scenes = [(lab + "@solution", [])]
        with open(os.path.join(stage, "labs", lab, "grading.json")) as f:
            scenes += [(s["name"], render_flags(s["options"])) for s in json.load(f)["scenes"]]
        for scene, flags in scenes:
            out = os.path.join(scratch, "expected", lab, scene)
            run([raster, "render", lab + "@solution", "--out-dir", out] + flags)
            with open(os.path.join(out, lab + "@solution.png"), "rb") as f:
                rendered = f.read()
            with open(os.path.join(reference, scene + ".png"), "rb") as f:
                shipped = f.read()
            checked += 1
            if rendered != shipped:
                problems.append("labs/%s/reference/%s.png is not what raster render %s@solution %s writes" %
                                (lab, scene, lab, " ".join(flags)))
    if checked < 16:
        problems.append("only %d reference images checked" % checked)
    print("handout_test: %d reference images equal to the solutions' renders, byte for byte" % checked)
    return problems


def grade(raster, submission, out, lab=None):
    argv = [raster, "grade", submission, "--public", "--out", out] + (["--lab", lab] if lab else [])
    said, seconds = run(argv)
    with open(os.path.join(out, "results.json")) as f:
        results = json.load(f)
    scores = {}
    for test in results["tests"]:
        lab_name = test["extra_data"]["lab"]
        got, most = scores.get(lab_name, (0, 0))
        scores[lab_name] = (got + test["score"], most + test["max_score"])
    return scores, seconds


def build(source, build_dir, cmake, work):
    out = os.path.join(build_dir, "handout")
    archive = os.path.join(out, NAME + ".tar.gz")
    if not os.path.isfile(archive):
        make_handout(source, build_dir, cmake)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with tarfile.open(archive) as tar:
        tar.extractall(work)
    root = os.path.join(work, NAME)
    problems = check_references(build_dir, os.path.join(out, NAME), work)
    # The README's commands, less .ci/setup: .ci/build (configure, build raster), then raster. Through
    # ccache where this build used it, with paths relative to the handout's root, so that its objects
    # are this build's (the same sources and flags).
    env = dict(os.environ)
    launcher = ""
    with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith("CMAKE_CXX_COMPILER_LAUNCHER:"):
                launcher = line.split("=", 1)[1].strip()
    if not launcher and os.environ.get("RASTER_HANDOUT_COLD") != "1":
        for p in problems:
            print("FAIL " + p)
        if os.environ.get("CI"):
            # .ci/build compiles through ccache where .ci/setup tests installed it: CI never skips.
            print("FAIL handout_test: in CI (CI is set) this build compiles without ccache: was it "
                  "configured by .ci/build with ccache installed (.ci/setup tests)?")
            return 1
        print("handout_test: skipped the handout's build: this build compiles without ccache, so the "
              "handout's would take minutes (RASTER_HANDOUT_COLD=1 runs it)")
        return 1 if problems else 77
    if launcher:
        env.update(CCACHE_BASEDIR=root, CCACHE_NOHASHDIR="1")
        run([cmake, "-S", root, "-B", os.path.join(root, "build"), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
             "-DCMAKE_CXX_COMPILER_LAUNCHER=" + launcher], env=env)
    said, seconds = run(["bash", os.path.join(root, ".ci", "build")], env=env, cwd=root)
    print("handout_test: .ci/build in the handout: %.1f s%s" % (seconds, " (ccache)" if launcher else ""))
    raster = os.path.join(root, "build", "bin", "raster")
    run([raster, "render", "billboards", "--out-dir", os.path.join(work, "out")], cwd=root)
    if not os.path.isfile(os.path.join(work, "out", "billboards.png")):
        problems.append("raster render billboards wrote no billboards.png")
    # The viewer's J compares with the shipped image of the solution (SDL's offscreen driver).
    said, _ = run([raster, "view", "billboards", "--headless", "--script", "j"], cwd=root)
    shipped = os.path.join(root, "labs", "billboards", "reference", "billboards@solution.png")
    if not re.search(r"difference from %s: [0-9]+ of 921600 pixels differ" % re.escape(shipped), said):
        problems.append("raster view billboards's J does not compare with %s: %s" % (shipped, said[-800:]))
    # As handed out: every lab below full marks, against the shipped images.
    scores, seconds = grade(raster, os.path.join(root, "labs"), os.path.join(work, "grade-labs"))
    print("handout_test: grade labs --public: %s (%.1f s)" % (scores, seconds))
    if len(scores) < 8 or any(got >= most or most <= 0 for got, most in scores.values()):
        problems.append("the handed-out labs do not all score below full marks: %s" % scores)
    # A solved lab (its solution without the markers) at full marks against the same images.
    solved = os.path.join(work, "solved", "billboards")
    os.makedirs(solved)
    text, _ = run([sys.executable, os.path.join(source, "labs", "generate.py"), "--root", source, "--solved",
                   "billboards"])
    with open(os.path.join(solved, "billboards.cpp"), "w") as f:
        f.write(text)
    scores, seconds = grade(raster, solved, os.path.join(work, "grade-solved"), "billboards")
    print("handout_test: the solved billboards: %s (%.1f s)" % (scores, seconds))
    if list(scores) != ["billboards"] or any(got != most or most <= 0 for got, most in scores.values()):
        problems.append("the solved billboards does not score full marks: %s" % scores)
    for p in problems:
        print("FAIL " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "leaks":
        sys.exit(leaks(*sys.argv[2:]))
    if len(sys.argv) == 6 and sys.argv[1] == "build":
        sys.exit(build(*sys.argv[2:]))
    sys.exit(__doc__)
