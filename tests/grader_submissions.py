#!/usr/bin/env python3
"""tests/grader's wrong submissions, made from today's solutions (tests/grader/README.md).

Each submission is a folder tests/grader/<name>/ of patches, <lab>.patch for each lab it holds: a
unified diff against solutions/<lab>/<lab>.cpp as a student would hand it in, its answers without
the stand-ins that labs/generate.py makes the handout of (`labs/generate.py --solved <lab>` prints
it), whose text before the diff says what the change is;
and, for a submission that holds symbolic links (which a patch cannot carry), a file `links`: lines
"<path in the submission> -> <target>", `#` lines comments. A patch's lines and a link's target may
hold @REPO@, replaced by the source tree's absolute path, and @CLASS@, by the folder of the class
that grade_cli_test.py's hostile case grades (the hostile submissions reach for paths of the machine
they are graded on, which differ from checkout to checkout).
The grade tests (grade_cli_test.py, gradescope_test.py) build the submission, laid out like labs/
(<name>/<lab>/<lab>.cpp), in a folder of their own with `materialise`; a patch that no longer applies
stops them with an error naming the patch, the hunk and the solution.

    grader_submissions.py check SOURCE_DIR            every patch applies and changes its solution
    grader_submissions.py make SOURCE_DIR NAME DIR    writes DIR/NAME/<lab>/<lab>.cpp, to look at

The patches apply with Debian's `patch` too, to that text; this module applies them itself (no
package needed) and more strictly: no fuzz, and a hunk whose lines are not at its place must be found
exactly once elsewhere in the solution.
"""
import importlib.util
import os
import re
import sys

GRADER = os.path.join("tests", "grader")
NOT_SUBMISSIONS = {"root"}  # tests/grader/root is a grading root (the small scenes), not a submission
LINKS = "links"
HUNK = re.compile(r"^@@ -(\d+)(?:,(\d+))? \+(\d+)(?:,(\d+))? @@")


class PatchError(Exception):
    """A patch that does not apply, or is not a patch: the message names the patch and the solution."""


def submission_names(source):
    folder = os.path.join(source, GRADER)
    return sorted(n for n in os.listdir(folder)
                  if os.path.isdir(os.path.join(folder, n)) and n not in NOT_SUBMISSIONS)


def patches_of(source, name):
    """{lab: path of its patch} for submission `name`; a folder holding anything but patches and a
    `links` file, or neither, is an error."""
    folder = os.path.join(source, GRADER, name)
    patches, others = {}, []
    for entry in sorted(os.listdir(folder)):
        if entry.endswith(".patch") and os.path.isfile(os.path.join(folder, entry)):
            patches[entry[:-len(".patch")]] = os.path.join(folder, entry)
        elif entry != LINKS or not os.path.isfile(os.path.join(folder, entry)):
            others.append(entry)
    if others or not (patches or links_of(source, name)):
        raise PatchError(f"{os.path.join(GRADER, name)} must hold only <lab>.patch files and a `{LINKS}` "
                         f"file, at least one of them (found {', '.join(others) or 'none'})")
    return patches


def links_of(source, name):
    """[(path in the submission, target)] of submission `name`'s `links` file ([] without one)."""
    path = os.path.join(source, GRADER, name, LINKS)
    if not os.path.isfile(path):
        return []
    links = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if not line.strip() or line.startswith("#"):
                continue
            relative, arrow, target = (part.strip() for part in line.partition(" -> "))
            if not arrow or not relative or not target or os.path.isabs(relative) or ".." in relative.split("/"):
                raise PatchError(f"{os.path.relpath(path, source)}:{number}: not \"<path in the submission> -> "
                                 f"<target>\" with a relative path that stays inside: {line.rstrip()!r}")
            links.append((relative, target))
    return links


def substitute(text, places):
    """`text` with each placeholder of `places` ({"@REPO@": path, ...}) replaced."""
    for placeholder, value in places.items():
        text = text.replace(placeholder, value)
    return text


def parse(text, where):
    """(note, hunks) of a unified diff: the note is the text before its `---` line; each hunk is
    (header, old start, old lines, new lines)."""
    lines = text.splitlines(keepends=True)
    start = next((i for i, line in enumerate(lines) if line.startswith("--- ")), None)
    if start is None or start + 1 >= len(lines) or not lines[start + 1].startswith("+++ "):
        raise PatchError(f"{where}: no `--- `/`+++ ` header: not a unified diff")
    note = "".join(lines[:start]).strip()
    hunks, i = [], start + 2
    while i < len(lines):
        m = HUNK.match(lines[i])
        if not m:
            raise PatchError(f"{where}: line {i + 1} is not a hunk header: {lines[i].rstrip()!r}")
        header, old_count, new_count = lines[i].rstrip(), int(m[2] or 1), int(m[4] or 1)
        old, new = [], []
        i += 1
        while i < len(lines) and (len(old) < old_count or len(new) < new_count):
            tag, body = lines[i][:1], lines[i][1:]
            if tag not in (" ", "-", "+"):
                raise PatchError(f"{where}: line {i + 1} in hunk {header}: {lines[i].rstrip()!r}")
            if tag in (" ", "-"):
                old.append(body)
            if tag in (" ", "+"):
                new.append(body)
            i += 1
        if (len(old), len(new)) != (old_count, new_count):
            raise PatchError(f"{where}: hunk {header} ends early ({len(old)} old, {len(new)} new lines)")
        hunks.append((header, int(m[1]), old, new))
    if not hunks:
        raise PatchError(f"{where}: no hunk")
    return note, hunks


def apply(original, patch_text, patch_name, solution_name):
    """`original` with the patch's hunks applied, each where its old lines are (the stated line, moved by
    what the hunks before it added or removed, else the one other place they are found)."""
    _, hunks = parse(patch_text, patch_name)
    lines = original.splitlines(keepends=True)
    out, done, shift = [], 0, 0  # done: lines of `original` consumed
    for number, (header, start, old, new) in enumerate(hunks, 1):
        def fits(at):
            return lines[at:at + len(old)] == old
        expected = max(start - 1 + shift, done) if old else start + shift
        at = expected if fits(expected) else None
        if at is None:
            places = [p for p in range(done, len(lines) - len(old) + 1) if fits(p)]
            if len(places) != 1:
                why = "its lines are nowhere" if not places else f"its lines are at {len(places)} places"
                raise PatchError(f"{patch_name}: hunk {number} ({header}) does not apply to {solution_name}: "
                                 f"{why} after line {done} (the solution changed there: update the patch):\n"
                                 + "".join(old))
            at = places[0]
        out += lines[done:at] + new
        done = at + len(old)
        shift = at - (start - 1)
    result = "".join(out + lines[done:])
    if result == original:
        raise PatchError(f"{patch_name}: leaves {solution_name} unchanged")
    return result


def solved(source, lab):
    """solutions/<lab>/<lab>.cpp of `source` without its stand-ins (labs/generate.py's `solved`)."""
    spec = importlib.util.spec_from_file_location("generate_labs", os.path.join(source, "labs", "generate.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.solved(source, lab)


def build(source, name, lab, patch):
    solution = os.path.join("solutions", lab, f"{lab}.cpp")
    path = os.path.join(source, solution)
    if not os.path.isfile(path):
        raise PatchError(f"{os.path.relpath(patch, source)}: no solution {solution} to apply it to")
    original = solved(source, lab)
    with open(patch, encoding="utf-8") as f:
        return apply(original, f.read(), os.path.relpath(patch, source), solution)


def materialise(source, name, target, places=None):
    """Writes submission `name` as target/name/<lab>/<lab>.cpp, each lab's solution with its patch
    applied, makes its links, and returns target/name (the folder `raster grade` takes). `places`:
    the placeholders' values (default: @REPO@ the source tree, resolved)."""
    places = places or {"@REPO@": os.path.realpath(source)}
    folder = os.path.join(target, name)
    os.makedirs(folder, exist_ok=True)
    for lab, patch in patches_of(source, name).items():
        text = substitute(build(source, name, lab, patch), places)
        os.makedirs(os.path.join(folder, lab), exist_ok=True)
        with open(os.path.join(folder, lab, f"{lab}.cpp"), "w", encoding="utf-8") as f:
            f.write(text)
    for relative, link_target in links_of(source, name):
        path = os.path.join(folder, relative)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if os.path.lexists(path):
            os.remove(path)
        os.symlink(substitute(link_target, places), path)
    return folder


def self_check_errors():
    """The applier refuses what it must: a hunk whose lines moved away, one found twice, a no-op."""
    original = "a\nb\nc\nd\ne\n"
    patch = "note\n--- a/x\n+++ b/x\n@@ -2,3 +2,3 @@\n b\n-c\n+C\n d\n"
    cases = [("a\nb\nc\nd\ne\n", "a\nb\nC\nd\ne\n"),  # at its place
             ("0\n0\na\nb\nc\nd\ne\n", "0\n0\na\nb\nC\nd\ne\n"),  # moved by two lines
             ("a\nb\nX\nd\ne\n", "nowhere"),  # the solution changed there
             ("b\nc\nd\nb\nc\nd\n", "2 places")]  # ambiguous
    errors = []
    for text, expected in cases:
        try:
            got = apply(text, patch, "p.patch", "s.cpp")
        except PatchError as e:
            got = str(e)
            if "p.patch" not in got or "s.cpp" not in got:
                errors.append(f"the error names neither the patch nor the solution: {got}")
        if expected not in got:
            errors.append(f"applied to {text!r}: {got!r}, expected {expected!r}")
    try:
        apply(original, "--- a/x\n+++ b/x\n@@ -2,1 +2,1 @@\n-b\n+b\n", "p.patch", "s.cpp")
        errors.append("a patch that changes nothing applied")
    except PatchError as e:
        if "unchanged" not in str(e):
            errors.append(f"a no-op patch: {e}")
    return errors


def check(source):
    """Every submission's patches apply to today's solutions and change them; each has a note and a
    case in grade_cli_test.py (which says what it must lose), and each case a folder."""
    import grade_cli_test  # here, not at the top: it imports this module
    errors = self_check_errors()
    names, count = submission_names(source), 0
    errors += [f"{os.path.join(GRADER, n)} has no case in grade_cli_test.py's CASES" for n in names
               if n not in grade_cli_test.CASES]
    errors += [f"grade_cli_test.py's case {n} has no folder in {GRADER}" for n in grade_cli_test.CASES
               if n not in names]
    for name in names:
        try:
            links_of(source, name)
            for lab, patch in patches_of(source, name).items():
                build(source, name, lab, patch)
                count += 1
                with open(patch, encoding="utf-8") as f:
                    if not parse(f.read(), patch)[0]:
                        errors.append(f"{os.path.relpath(patch, source)}: no note before the diff says what it changes")
        except PatchError as e:
            errors.append(str(e))
    print(f"{len(names)} submissions, {count} patches checked")
    return errors


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "check":
        errors = check(os.path.abspath(sys.argv[2]))
        for e in errors:
            print("FAILED:", e)
        return 1 if errors else 0
    if len(sys.argv) == 5 and sys.argv[1] == "make":
        print(materialise(os.path.abspath(sys.argv[2]), sys.argv[3], sys.argv[4]))
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
