#!/usr/bin/env python3
"""Each lab has one source (labs/README.md, "One source per lab"): every labs/<lab>/<lab>.cpp is what
labs/generate.py makes of solutions/<lab>/<lab>.cpp, byte for byte, and the solutions' marker pairs
are well formed, their places numbered as the labs' READMEs number them.

    lab_sources_test.py SOURCE_DIR

Then the check is shown to fail: on a copy of billboards, labs/CMakeLists.txt and labs/README.md in a
scratch folder, each case below spoils one thing (a number swapped, an END missing, the handout edited
by hand, ...) and the check must fail with a message that names the file and the line.
"""
import contextlib
import importlib.util
import io
import os
import shutil
import sys
import tempfile

LAB = "billboards"
SOLUTION = f"solutions/{LAB}/{LAB}.cpp"
HANDOUT = f"labs/{LAB}/{LAB}.cpp"


def load_generate(source):
    spec = importlib.util.spec_from_file_location("generate_labs", os.path.join(source, "labs", "generate.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_check(generate, root):
    """(exit status, printed text) of `generate.py --check --root root`."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = generate.main(["--check", "--root", root])
    return status, out.getvalue()


def line_of(text, needle, nth=1):
    """The 1-based number of the line holding `needle` for the nth time."""
    hits = [i for i, line in enumerate(text.splitlines(), 1) if needle in line]
    return hits[nth - 1]


def replace_line(text, needle, new, nth=1):
    """`text` with the nth line holding `needle` replaced by `new` (None: removed)."""
    lines = text.splitlines(keepends=True)
    i = line_of(text, needle, nth) - 1
    lines[i:i + 1] = [] if new is None else [new + "\n"]
    return "".join(lines)


def cases(solution, handout, readme):
    """(name, the file spoilt, its new text, the text the message must hold) of each spoilt copy."""
    s = solution
    begin2, begin3, end3 = line_of(s, "// BEGIN LAB 2"), line_of(s, "// BEGIN LAB 3"), line_of(s, "// END LAB 3")
    return [
        ("numbers swapped", SOLUTION,
         s.replace("LAB 1\n", "LAB 9\n").replace("LAB 2\n", "LAB 1\n").replace("LAB 9\n", "LAB 2\n"),
         f"{SOLUTION}:{begin2}: LAB 1 out of order: after LAB 2"),
        ("END missing", SOLUTION, replace_line(s, "// END LAB 3", None),
         f"{SOLUTION}:{line_of(s, '// BEGIN LAB 4') - 1}: `BEGIN LAB 4` inside LAB 3, begun on line {begin3}"),
        ("END missing at the end", SOLUTION, s[:s.rindex("// END LAB 4")],
         f"{SOLUTION}:{line_of(s, '// BEGIN LAB 4')}: `BEGIN LAB 4` has no `END LAB 4`"),
        ("END of another", SOLUTION, replace_line(s, "// END LAB 3", "// END LAB 4"),
         f"{SOLUTION}:{end3}: `END LAB 4` ends LAB 3"),
        ("BEGIN missing", SOLUTION, replace_line(s, "// BEGIN LAB 3", None),
         f"{SOLUTION}:{line_of(s, '// STAND-IN', 4) - 1}: `STAND-IN` outside a BEGIN/END pair"),
        ("stand-in lines left over", SOLUTION, replace_line(s, "// BEGIN LAB 3", None),
         f"{SOLUTION}:{line_of(s, '// STAND-IN', 4)}: `//>` lines outside a stand-in, to line {end3 - 2}"),
        ("nested", SOLUTION, replace_line(s, "// BEGIN LAB 3", "// BEGIN LAB 3\n// BEGIN NOTE"),
         f"{SOLUTION}:{begin3 + 1}: `BEGIN NOTE` inside LAB 3"),
        ("unknown marker", SOLUTION, replace_line(s, "// BEGIN LAB 3", "// BEGIN LAB three"),
         f"{SOLUTION}:{begin3}: unknown marker `BEGIN LAB three`"),
        ("no STAND-IN", SOLUTION, replace_line(s, "// STAND-IN", "//", 4),
         f"{SOLUTION}:{end3}: LAB 3, begun on line {begin3}, has no `// STAND-IN` line"),
        ("stand-in line without //>", SOLUTION,
         replace_line(s, "//> BlendState fireBlend() {", "BlendState fireBlend() {"),
         f"{SOLUTION}:{line_of(s, '//> BlendState fireBlend() {')}: a line of LAB 3's stand-in"),
        ("a number twice", SOLUTION, s.replace("LAB 4\n", "LAB 2\n"),
         f"{SOLUTION}:{line_of(s, '// BEGIN LAB 4')}: LAB 2 again (its place begins on line {begin2}"),
        ("a number the README lacks", SOLUTION, s.replace("LAB 4\n", "LAB 5\n"),
         f"{SOLUTION}:{line_of(s, '// BEGIN LAB 4')}: LAB 5, which labs/README.md does not name"),
        ("a place the README names missing", SOLUTION, s.replace("LAB 4\n", "LAB 5\n"),
         f"labs/README.md:{line_of(readme, '| LAB 4 ')}: LAB 4, which {SOLUTION} has no place for"),
        ("code in a NOTE", SOLUTION, replace_line(s, "// END NOTE", "//> int x;\n// END NOTE"),
         f"{SOLUTION}:1: the NOTE's two sides differ in code"),
        ("answer as stand-in", SOLUTION,
         replace_line(s, "//> return {1.0f, 0.5f, 0.1f, 1.0f};",
                      "        //> return billboardTexture->Sample(sampler, in.tex);")
         .replace("        //> (void)in;\n", ""),
         f"{SOLUTION}:{line_of(s, '// BEGIN LAB 2')}: LAB 2's stand-in is its answer"),
        ("handout edited", HANDOUT, None,
         f"{HANDOUT}:{line_of(handout, 'Fill in the four places')}: differs from what generate.py makes of "
         "its solution"),
        ("handout names a missing place", SOLUTION, replace_line(s, "// END NOTE", "//> // LAB 7 too\n// END NOTE"),
         f"{HANDOUT}:{line_of(handout, 'Look at labs/billboards/README.md') + 1} (as made): names LAB 7"),
    ]


def scratch_copy(source, folder):
    for path in (SOLUTION, HANDOUT, "labs/README.md"):
        os.makedirs(os.path.dirname(os.path.join(folder, path)), exist_ok=True)
        shutil.copyfile(os.path.join(source, path), os.path.join(folder, path))
    with open(os.path.join(folder, "labs", "CMakeLists.txt"), "w", encoding="utf-8") as f:
        f.write(f"raster_add_lab({LAB})\n")


def main(source):
    generate = load_generate(source)
    errors = []
    status, text = run_check(generate, source)
    if status != 0:
        errors.append(f"the source tree fails the check:\n{text}")
    with tempfile.TemporaryDirectory() as scratch:
        scratch_copy(source, scratch)
        status, text = run_check(generate, scratch)
        if status != 0:
            errors.append(f"the unspoilt copy of {LAB} fails the check:\n{text}")
        with open(os.path.join(source, SOLUTION), encoding="utf-8") as f:
            solution = f.read()
        with open(os.path.join(source, HANDOUT), encoding="utf-8") as f:
            handout = f.read()
        with open(os.path.join(source, "labs", "README.md"), encoding="utf-8") as f:
            readme = f.read()
        for name, path, text, expected in cases(solution, handout, readme):
            if path == HANDOUT:
                text = handout.replace("Fill in the four places", "Fill in the 4 places")
            with open(os.path.join(scratch, path), "w", encoding="utf-8") as f:
                f.write(text)
            status, printed = run_check(generate, scratch)
            if os.environ.get("LAB_SOURCES_VERBOSE"):
                print(f"--- {name}:\n{printed}", end="")
            if status == 0 or expected not in printed:
                errors.append(f"{name}: exit {status}, the message lacks {expected!r}:\n{printed}")
            scratch_copy(source, scratch)
        print(f"lab_sources: {len(generate.labs_of(source))} labs made from their solutions, "
              f"{len(cases(solution, handout, readme))} spoilt copies refused")
    for e in errors:
        print(f"FAILED: {e}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
