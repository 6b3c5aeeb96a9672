#!/usr/bin/env python3
"""Gradescope's autograder zip end to end (docs/GRADING.md, "Grading on Gradescope").

    gradescope_test.py SOURCE_DIR BUILD_DIR WORK_DIR CMAKE

Makes the zip (raster/tools/grade/gradescope/autograder_zip.cmake), unpacks it into WORK_DIR/autograder
laid out like Gradescope's /autograder (source/, submission/, results/, run_autograder), runs setup.sh
on the grader already built in BUILD_DIR (RASTER_AUTOGRADER_PREBUILT: no packages, no compile), then
run_autograder on: billboards' solution as a loose file (full marks), a wrong submission of
tests/grader/ in its lab folder (less), an empty submission (0, with a message) and a grader that is
missing (0, with the reason). Each results.json is checked against Gradescope's specification; the
search for a lab's file in an upload is checked on layouts made here. Exit status 0 when every check
holds, 1 with what did not.
"""
import importlib.machinery
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile

import grader_submissions

LAB = "billboards"
# tests/grader/'s submission that crashes in the geometry shader: it loses every scene with particles
# (the real ones all have them), and quickly: no diagnosis (a picture defect's costs two traced renders
# a scene, 30 s in all on this machine under load, against a minute for the whole test).
WRONG = "crash"
# Gradescope's autograder specification, "Output format": the fields a results.json may hold.
TOP_FIELDS = {"score", "execution_time", "output", "output_format", "test_output_format", "test_name_format",
              "visibility", "stdout_visibility", "extra_data", "tests", "leaderboard"}
TEST_FIELDS = {"score", "max_score", "status", "name", "name_format", "number", "output", "output_format",
               "tags", "visibility", "extra_data"}
VISIBILITIES = {"hidden", "after_due_date", "after_published", "visible"}
FORMATS = {"text", "html", "simple_format", "md", "ansi"}


def spec_errors(results):
    """What in a parsed results.json breaks Gradescope's specification."""
    errors = []
    number = (int, float)
    if not isinstance(results, dict):
        return ["results.json is not a JSON object"]
    errors += [f"unknown top-level field {k!r}" for k in results if k not in TOP_FIELDS]
    tests = results.get("tests", [])
    if not isinstance(tests, list):
        return errors + ["tests is not an array"]
    if "score" in results and not isinstance(results["score"], number):
        errors.append(f"score {results['score']!r} is not a number")
    if "score" not in results and not all(isinstance(t, dict) and "score" in t for t in tests):
        errors.append("no top-level score and a test without one")
    for key in ("output",):
        if key in results and not isinstance(results[key], str):
            errors.append(f"top-level {key} is not a string")
    for key in ("visibility", "stdout_visibility"):
        if key in results and results[key] not in VISIBILITIES:
            errors.append(f"top-level {key} {results[key]!r} is not one of {sorted(VISIBILITIES)}")
    for key in ("output_format", "test_output_format", "test_name_format"):
        if key in results and results[key] not in FORMATS:
            errors.append(f"{key} {results[key]!r} is not one of {sorted(FORMATS)}")
    for i, t in enumerate(tests):
        where = f"tests[{i}]"
        if not isinstance(t, dict):
            errors.append(f"{where} is not an object")
            continue
        errors += [f"{where}: unknown field {k!r}" for k in t if k not in TEST_FIELDS]
        for key in ("score", "max_score"):
            if key in t and not isinstance(t[key], number):
                errors.append(f"{where}.{key} {t[key]!r} is not a number")
        for key in ("name", "number", "output"):
            if not isinstance(t.get(key), str) or not t[key]:
                errors.append(f"{where}.{key} is missing or not a non-empty string")
        if t.get("visibility", "visible") not in VISIBILITIES:
            errors.append(f"{where}.visibility {t['visibility']!r} is not one of {sorted(VISIBILITIES)}")
        if t.get("status", "passed") not in ("passed", "failed"):
            errors.append(f"{where}.status {t['status']!r} is neither passed nor failed")
    return errors


def make_zip(source, cmake, zip_path):
    script = os.path.join(source, "raster", "tools", "grade", "gradescope", "autograder_zip.cmake")
    # One lab, as a Gradescope assignment is: a loose billboards.cpp then scores full marks.
    subprocess.run([cmake, f"-DSOURCE_DIR={source}", f"-DOUTPUT={zip_path}", "-DLABS=billboards", "-P", script], check=True,
                   capture_output=True, text=True)


def zip_errors(archive):
    """The zip's root holds both scripts, executable, and the tree setup.sh builds from; no tests/, docs/."""
    names = {i.filename: (i.external_attr >> 16) for i in archive.infolist()}
    errors = []
    for script in ("setup.sh", "run_autograder"):
        if script not in names:
            errors.append(f"the zip's root has no {script}")
        elif not names[script] & 0o100:
            errors.append(f"{script} is not executable in the zip (mode {oct(names[script])})")
    for needed in ("CMakeLists.txt", "raster/CMakeLists.txt", "labs/CMakeLists.txt", f"labs/{LAB}/{LAB}.cpp",
                   f"labs/{LAB}/grading.json", f"solutions/{LAB}/{LAB}.cpp", f"solutions/{LAB}/grading.json",
                   "raster/tools/grade/lab_runner_main.cpp"):
        if needed not in names:
            errors.append(f"the zip lacks {needed}")
    errors += [f"the zip holds {n}" for n in names if n.split("/")[0] in ("tests", "docs", "build", ".git")]
    return errors


def unpack(archive, target):
    """As Gradescope does, with each file's mode kept (Python's zipfile drops it)."""
    for info in archive.infolist():
        path = archive.extract(info, target)
        mode = info.external_attr >> 16
        if mode and not info.is_dir():
            os.chmod(path, mode & 0o777)


def package_errors(source):
    """setup.sh installs nothing that .ci/setup does not."""
    def packages(path):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        return {p for group in re.findall(r"packages\+?=\(([^)]*)\)", text) for p in group.split()}
    ours = packages(os.path.join(source, "raster", "tools", "grade", "gradescope", "setup.sh"))
    ci = packages(os.path.join(source, ".ci", "setup"))
    return [f"setup.sh installs {p}, which .ci/setup does not" for p in sorted(ours - ci)] + \
        ([] if ours else ["setup.sh lists no packages"])


def load_run_autograder(path):
    loader = importlib.machinery.SourceFileLoader("run_autograder", path)
    spec = importlib.util.spec_from_loader("run_autograder", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def layout_errors(module):
    """find_lab_files on uploads laid out as students upload them."""
    cases = [  # (files of the upload, links, expected file graded or None, words in the notes)
        ({f"{LAB}.cpp": "a"}, {}, f"{LAB}.cpp", []),
        ({f"{LAB}/{LAB}.cpp": "a"}, {}, f"{LAB}/{LAB}.cpp", []),
        ({f"raster-main/labs/{LAB}/{LAB}.cpp": "a", f"raster-main/solutions/{LAB}/{LAB}.cpp": "b",
          f"raster-main/tests/grader/x/{LAB}/{LAB}.cpp": "c"}, {}, f"raster-main/labs/{LAB}/{LAB}.cpp",
         ["also found: raster-main/solutions"]),
        ({"main.cpp": "a", f"__MACOSX/._{LAB}.cpp": "b"}, {}, "main.cpp", ["its only C++ file"]),
        ({"a.cpp": "a", "b.cpp": "b"}, {}, None, [f"no {LAB}.cpp", "a.cpp, b.cpp"]),
        ({}, {f"{LAB}.cpp": "/etc/hostname"}, None, ["not a regular file"]),
        ({}, {}, None, [f"no {LAB}.cpp in the submission (C++ files found: none)"]),
    ]
    errors = []
    for files, links, expected, words in cases:
        with tempfile.TemporaryDirectory() as upload:
            for relative, text in files.items():
                os.makedirs(os.path.dirname(os.path.join(upload, relative)), exist_ok=True)
                with open(os.path.join(upload, relative), "w", encoding="utf-8") as f:
                    f.write(text)
            for relative, target in links.items():
                os.symlink(target, os.path.join(upload, relative))
            chosen, notes = module.find_lab_files(upload, [LAB])
            text = "\n".join(notes)
            if chosen.get(LAB) != expected:
                errors.append(f"upload {sorted(files) + sorted(links)}: graded {chosen.get(LAB)}, not {expected}")
            errors += [f"upload {sorted(files)}: the notes lack {w!r}:\n{text}" for w in words if w not in text]
    return errors


def cpu_check_errors(module):
    """run_autograder's check of the processor against the -march setup.sh built for."""
    v3 = "fpu sse2 ssse3 sse4_2 popcnt avx avx2 fma bmi2 movbe f16c"
    cases = [  # (autograder_march.txt or None, cpuinfo flags, expected (march, lacking))
        ("x86-64-v3", v3, ("x86-64-v3", [])),
        ("x86-64-v3", "fpu sse2 ssse3 sse4_2 popcnt avx", ("x86-64-v3", ["avx2", "fma", "bmi2", "movbe", "f16c"])),
        ("", "fpu sse2", ("", [])),  # the baseline: runs anywhere
        (None, "fpu sse2", ("", [])),  # no file: a build that did not say (prebuilt)
    ]
    errors = []
    for march, flags, expected in cases:
        with tempfile.TemporaryDirectory() as source:
            os.makedirs(os.path.join(source, "build"))
            if march is not None:
                with open(os.path.join(source, "build", "autograder_march.txt"), "w", encoding="utf-8") as f:
                    f.write(march + "\n")
            cpuinfo = os.path.join(source, "cpuinfo")
            with open(cpuinfo, "w", encoding="utf-8") as f:
                f.write(f"processor\t: 0\nflags\t\t: {flags}\n\nprocessor\t: 1\nflags\t\t: {flags}\n")
            got = module.missing_cpu_features(source, cpuinfo)
            if got != expected:
                errors.append(f"march {march!r} on flags {flags!r}: {got}, not {expected}")
    return errors


def run_autograder(root, env):
    """Runs root/run_autograder as Gradescope does (working directory root) and reads results.json."""
    results = os.path.join(root, "results", "results.json")
    if os.path.exists(results):
        os.remove(results)
    start = time.monotonic()
    done = subprocess.run([os.path.join(root, "run_autograder")], cwd=root, env=env, capture_output=True,
                          text=True, timeout=300)
    print(f"run_autograder: {time.monotonic() - start:.1f} s, exit status {done.returncode}")
    print(done.stdout[-3000:], done.stderr[-3000:])
    if done.returncode != 0:
        raise SystemExit(f"run_autograder exited with {done.returncode}, not 0")
    with open(results, encoding="utf-8") as f:
        return json.load(f)


def fill_submission(root, files):
    submission = os.path.join(root, "submission")
    shutil.rmtree(submission, ignore_errors=True)
    os.makedirs(submission)
    for relative, source in files.items():
        os.makedirs(os.path.dirname(os.path.join(submission, relative)), exist_ok=True)
        shutil.copyfile(source, os.path.join(submission, relative))


def total(results):
    return sum(t["max_score"] for t in results["tests"])


def case_errors(name, results, check):
    errors = [f"{name}: {e}" for e in spec_errors(results)]
    if not errors:
        errors += [f"{name}: {e}" for e in check(results)]
    return errors


def grade_errors(source, root, env, made):
    errors = []
    solution = os.path.join(source, "solutions", LAB, f"{LAB}.cpp")
    # tests/grader/crash/billboards.patch applied to today's solution (tests/grader_submissions.py).
    wrong = os.path.join(grader_submissions.materialise(source, WRONG, made), LAB, f"{LAB}.cpp")
    cases = [
        ("the solution, a loose file", {f"{LAB}.cpp": solution},
         lambda r: [] if r["tests"] and r["score"] == total(r) > 0 and f"{LAB}: graded {LAB}.cpp" in r["output"]
         else [f"score {r['score']} of {total(r)}, not full marks, or no note of the file graded"]),
        (f"{WRONG}, a lab's folder", {f"{LAB}/{LAB}.cpp": wrong},
         lambda r: [] if r["tests"] and 0 <= r["score"] < total(r) and any(
             t["score"] == 0 and "crashed: " in t["output"] for t in r["tests"])
         else [f"score {r['score']} of {total(r)}: not less than full marks with the crash named"]),
        ("an empty submission", {},
         lambda r: [] if r["tests"] and r["score"] == 0 and f"no {LAB}.cpp in the submission" in r["output"]
         else [f"score {r['score']}, or no message naming the missing {LAB}.cpp: {r.get('output')!r}"]),
    ]
    for name, files, check in cases:
        fill_submission(root, files)
        errors += case_errors(name, run_autograder(root, env), check)
    errors += unisolated_errors(source, root, env, made)
    # A grader that is gone (a failed setup.sh): still a valid results.json, 0, the reason given.
    build = os.path.join(root, "source", "build")
    os.rename(build, build + ".away")
    try:
        errors += case_errors("no grader", run_autograder(root, env), lambda r: [] if r["score"] == 0 and (
            "setup.sh" in r.get("output", "")) else [f"score {r['score']}, output {r.get('output')!r}"])
    finally:
        os.rename(build + ".away", build)
    return errors


def unisolated_errors(source, root, env, made):
    """What holds on Gradescope where the kernel's isolation does not (a container whose seccomp refuses
    Landlock, without user namespaces for bubblewrap): `--isolation none`, as root, so that the
    submission runs as nobody and setup.sh's locks are all that keep it out. The hostile submission
    that includes the solution by its absolute path, and the one that reads it at run time
    (tests/grader/, @REPO@ this folder laid out like /autograder/source), score nothing and read
    nothing."""
    if os.geteuid() != 0:
        print("gradescope: not root: the submission would run as this user; the locks are not checked")
        return []
    places = {"@REPO@": os.path.join(root, "source")}
    solution = os.path.join(root, "source", "solutions", LAB, f"{LAB}.cpp")
    env = dict(env, RASTER_AUTOGRADER_ISOLATION="none")
    errors = []
    for name, words in (("include_absolute", f"compile refused: your file includes {solution}, which is not part"),
                        ("print_solution", f"cannot read {solution}: Permission denied")):
        made_file = os.path.join(grader_submissions.materialise(source, name, made, places), LAB, f"{LAB}.cpp")
        fill_submission(root, {f"{LAB}/{LAB}.cpp": made_file})
        errors += case_errors(f"{name}, unisolated", run_autograder(root, env), lambda r, words=words: [] if (
            r["tests"] and r["score"] == 0 and "sandbox: no file-system isolation" in r["output"]
            and all(words in t["output"] and "LEAKED" not in t["output"] for t in r["tests"]))
            else [f"score {r['score']}, or a scene without {words!r} or with LEAKED: {r['tests'][:1]}"])
    return errors


def setup_errors(root, env):
    done = subprocess.run(["bash", os.path.join(root, "source", "setup.sh")], cwd=os.path.join(root, "source"),
                          env=env, capture_output=True, text=True, timeout=120)
    print(done.stdout, done.stderr)
    if done.returncode != 0:
        return [f"setup.sh exited with {done.returncode}"]
    mode = os.stat(os.path.join(root, "source", "solutions")).st_mode
    return [] if mode & 0o077 == 0 else [f"solutions/ is mode {oct(mode & 0o777)}, open to others"]


def main():
    source, build, work = map(os.path.abspath, sys.argv[1:4])
    cmake = sys.argv[4]
    top = os.path.join(work, "gradescope")
    shutil.rmtree(top, ignore_errors=True)
    root = os.path.join(top, "autograder")
    for folder in ("source", "submission", "results"):
        os.makedirs(os.path.join(root, folder))
    # Searchable by all, as /autograder is: a root grader's builds run as nobody.
    for folder in (top, root):
        os.chmod(folder, 0o755)
    zip_path = os.path.join(top, "autograder.zip")
    make_zip(source, cmake, zip_path)
    errors = package_errors(source)
    with zipfile.ZipFile(zip_path) as archive:
        errors += zip_errors(archive)
        unpack(archive, os.path.join(root, "source"))
    shutil.copy2(os.path.join(root, "source", "run_autograder"), os.path.join(root, "run_autograder"))
    module = load_run_autograder(os.path.join(root, "run_autograder"))
    errors += layout_errors(module) + cpu_check_errors(module)
    env = dict(os.environ, AUTOGRADER_ROOT=root, RASTER_AUTOGRADER_PREBUILT=build, RASTER_AUTOGRADER_JOBS="2")
    errors += setup_errors(root, env)
    if not errors:
        errors += grade_errors(source, root, env, os.path.join(top, "made"))
    for e in errors:
        print("FAILED:", e)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
