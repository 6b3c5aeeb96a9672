#!/usr/bin/env python3
"""Writes each lab as handed out, labs/<lab>/<lab>.cpp, from its solution, solutions/<lab>/<lab>.cpp.

The solution is the one source of a lab (labs/README.md, "One source per lab"). Where the handout
differs from it, the solution marks the place with a begin/end pair of comment lines around its own
lines, followed by the handout's, each of those behind `//>`:

    // BEGIN LAB 3        a student's place, numbered as the lab's README numbers them
    <the answer>          the solution's lines: left out of the handout
    // STAND-IN
    //> <the stand-in>    the handout's lines: `//>` and one space after it taken out, the indent
    // END LAB 3          before `//>` kept (a bare `//>` is an empty line)

    // BEGIN NOTE         wording that differs and is no place (the file's header, a comment):
    ...                   the same as a place, but its two sides must be the same code once
    // END NOTE           comments and white space are taken out

Every line outside the pairs is the handout's too, verbatim, but the slides' `// slide: NAME` and
`// end slide: NAME` lines (slides/README.md), which neither the handout nor the solved text keeps. The places appear in the increasing
order of their numbers, each number once; a place may take several pairs one right after the other
(a constant its stand-in needs, then the function), and one that the lab's order puts elsewhere in
the file says so: `// BEGIN LAB 4 (out of order)`. The numbers are 1 to n, those of the lab's README
table (`| LAB n ...` rows of labs/<lab>/README.md, or of the lab's section in labs/README.md).

    generate.py [--root DIR] [LAB...]          writes the handouts (default: every lab with a solution)
    generate.py --check [--root DIR] [LAB...]  writes nothing; prints each marker error and each
                                               handout that differs from what it would write, exit 1
    generate.py --solved LAB                   prints the solution without its pairs' marker and
                                               stand-in lines: the answers as a student hands them in
"""
import argparse
import collections
import difflib
import os
import re
import sys

LABS_LIST = os.path.join("labs", "CMakeLists.txt")
BEGIN = re.compile(r"^(\s*)// BEGIN\b\s*(.*?)\s*$")
END = re.compile(r"^(\s*)// END\b\s*(.*?)\s*$")
STAND_IN = re.compile(r"^\s*// STAND-IN\s*$")
HANDOUT_LINE = re.compile(r"^(\s*)//>(?: (.*))?$")
PLACE = re.compile(r"^LAB ([1-9][0-9]*)( \(out of order\))?$")
NOTE = "NOTE"
# The slides' marker pairs (slides/README.md, "Code on a slide"): the solution's alone, in neither the
# handout nor the solved text.
SLIDE_MARKER = re.compile(r"^\s*// (?:end )?slide: [A-Za-z0-9_-]+\s*$")
README_PLACE = re.compile(r"^\|\s*LAB ([0-9]+)\b")


Parsed = collections.namedtuple("Parsed", "handout solved regions errors")


class Region:
    """One begin/end pair: its kind ("LAB n" or "NOTE"), number (None for a note), the line it begins
    on (1-based), the solution's lines and the handout's lines (decoded)."""

    def __init__(self, kind, number, out_of_order, line):
        self.kind, self.number, self.out_of_order, self.line = kind, number, out_of_order, line
        self.answer, self.handout, self.separated = [], [], False


def parse(text, where):
    """Parsed(handout, solved, regions, errors) of a solution's text: the handout's text, the
    solution's without the pairs' marker and stand-in lines, the pairs, and the errors, each
    "<where>:<line>: <what>"."""
    out, solved, regions, errors, open_region, orphans = [], [], [], [], None, None
    for number, line in enumerate(text.splitlines(keepends=True), 1):
        body = line.rstrip("\r\n")
        if SLIDE_MARKER.match(body):
            continue
        begin, end, handout = BEGIN.match(body), END.match(body), HANDOUT_LINE.match(body)
        if begin:
            kind = begin[2]
            place = PLACE.match(kind)
            if open_region:
                errors.append(f"{where}:{number}: `BEGIN {kind}` inside {open_region.kind}, begun on line "
                              f"{open_region.line} and not ended (pairs do not nest)")
            if not place and kind != NOTE:
                errors.append(f"{where}:{number}: unknown marker `BEGIN {kind}` (known: `BEGIN LAB <n>`, "
                              f"`BEGIN LAB <n> (out of order)`, `BEGIN {NOTE}`)")
                kind = "?"
            open_region = Region(kind.removesuffix(" (out of order)"), int(place[1]) if place else None,
                                 bool(place and place[2]), number)
            regions.append(open_region)
        elif end:
            if not open_region:
                errors.append(f"{where}:{number}: `END {end[2]}` with no BEGIN before it")
            else:
                if end[2] != open_region.kind and open_region.kind != "?":
                    errors.append(f"{where}:{number}: `END {end[2]}` ends {open_region.kind}, begun on line "
                                  f"{open_region.line}: say `END {open_region.kind}`")
                if not open_region.separated:
                    errors.append(f"{where}:{number}: {open_region.kind}, begun on line {open_region.line}, "
                                  f"has no `// STAND-IN` line (the handout's text follows one, maybe none)")
            open_region = None
        elif STAND_IN.match(body):
            if not open_region:
                errors.append(f"{where}:{number}: `STAND-IN` outside a BEGIN/END pair")
            elif open_region.separated:
                errors.append(f"{where}:{number}: a second `STAND-IN` in {open_region.kind}, begun on line "
                              f"{open_region.line}")
            else:
                open_region.separated = True
        elif open_region and open_region.separated:
            if not handout:
                errors.append(f"{where}:{number}: a line of {open_region.kind}'s stand-in (begun on line "
                              f"{open_region.line}) that does not start with `//>`: {body.strip()[:60]!r}")
                continue
            decoded = handout[1] + handout[2] if handout[2] else ""
            open_region.handout.append(decoded + line[len(body):])
            out.append(decoded + line[len(body):])
        elif handout:  # one message for a run of them
            first = orphans[0] if orphans and orphans[1] == number - 1 else number
            if first != number:
                errors.pop()
            orphans = (first, number)
            errors.append(f"{where}:{first}: a `//>` line outside a stand-in (it would be lost)" if first == number else
                          f"{where}:{first}: `//>` lines outside a stand-in, to line {number} (they would be lost)")
        elif open_region:
            open_region.answer.append(line)
            solved.append(line)
        else:
            out.append(line)
            solved.append(line)
    if open_region:
        errors.append(f"{where}:{open_region.line}: `BEGIN {open_region.kind}` has no `END {open_region.kind}`")
    return Parsed("".join(out), "".join(solved), regions, errors)


def code_of(lines):
    """The C++ of `lines` without its comments and white space (string and character literals kept)."""
    text, out, i = "".join(lines), [], 0
    while i < len(text):
        c = text[i]
        if text.startswith("//", i):
            i = text.find("\n", i) if "\n" in text[i:] else len(text)
        elif text.startswith("/*", i):
            i = text.find("*/", i + 2) + 2 if "*/" in text[i + 2:] else len(text)
        elif c in "\"'":
            j = i + 1
            while j < len(text) and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            if not c.isspace():
                out.append(c)
            i += 1
    return "".join(out)


def expected_numbers(root, lab):
    """{n: line} of the place numbers the lab's README table names (the line of its first row), and
    the README's path: labs/<lab>/README.md, or the lab's section of labs/README.md."""
    own = os.path.join(root, "labs", lab, "README.md")
    path = own if os.path.isfile(own) else os.path.join(root, "labs", "README.md")
    numbers, inside = {}, path == own
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if path != own and line.startswith("## "):
                inside = line.split()[1] == lab
            m = README_PLACE.match(line)
            if inside and m:
                numbers.setdefault(int(m[1]), number)
    return numbers, os.path.relpath(path, root)


def check_places(regions, numbers, readme, where):
    """Errors of the places' numbers: each place once (in one pair, or in pairs one right after the
    other), in increasing order (but those marked out of order), the README's; and of each region's
    two sides."""
    errors, places, previous, last = [], {}, None, 0
    for r in regions:
        if r.number is None:
            if r.kind == NOTE and code_of(r.answer) != code_of(r.handout):
                errors.append(f"{where}:{r.line}: the NOTE's two sides differ in code, not only in comments "
                              f"and white space: make it a place (`BEGIN LAB <n>`)")
            continue
        if r.number == previous:  # the same place, in another pair
            places[r.number].append(r)
            continue
        previous = r.number
        if r.number in places:
            errors.append(f"{where}:{r.line}: LAB {r.number} again (its place begins on line "
                          f"{places[r.number][0].line}; a place's pairs follow one another)")
            continue
        places[r.number] = [r]
        if not r.out_of_order:
            if r.number < last:
                errors.append(f"{where}:{r.line}: LAB {r.number} out of order: after LAB {last} (places go in "
                              f"increasing order; one that must sit elsewhere says `BEGIN LAB {r.number} "
                              f"(out of order)`)")
            last = max(last, r.number)
    for number, parts in places.items():
        if code_of(sum((p.answer for p in parts), [])) == code_of(sum((p.handout for p in parts), [])):
            errors.append(f"{where}:{parts[0].line}: LAB {number}'s stand-in is its answer (the same code)")
    for number in sorted(set(places) - set(numbers)):
        errors.append(f"{where}:{places[number][0].line}: LAB {number}, which {readme} does not name "
                      f"(it names LAB {', '.join(map(str, sorted(numbers))) or 'none'})")
    for number in sorted(set(numbers) - set(places)):
        errors.append(f"{readme}:{numbers[number]}: LAB {number}, which {where} has no place for")
    if set(numbers) != set(range(1, len(numbers) + 1)):
        errors.append(f"{readme}: the places are not numbered 1 to {len(numbers)}: LAB {sorted(numbers)}")
    return errors


def labs_of(root):
    """The labs registered in labs/CMakeLists.txt that have a solution."""
    with open(os.path.join(root, LABS_LIST), encoding="utf-8") as f:
        names = re.findall(r"^raster_add_lab\(([\w-]+)\)", f.read(), re.M)
    return [n for n in names if os.path.isfile(os.path.join(root, "solutions", n, f"{n}.cpp"))]


def read_solution(root, lab):
    solution = os.path.join("solutions", lab, f"{lab}.cpp")
    with open(os.path.join(root, solution), encoding="utf-8", newline="") as f:
        return parse(f.read(), solution)


def solved(root, lab):
    """The solution's text as a student would hand it in: the answers, no marker or stand-in line
    (tests/grader's patches apply to it)."""
    return read_solution(root, lab).solved


def generate(root, lab):
    """(handout text, errors) of one lab."""
    parsed = read_solution(root, lab)
    numbers, readme = expected_numbers(root, lab)
    where = os.path.join("solutions", lab, f"{lab}.cpp")
    errors = parsed.errors + check_places(parsed.regions, numbers, readme, where)
    for line, text in enumerate(parsed.handout.splitlines(), 1):
        for n in re.findall(r"\bLAB ([0-9]+)", text):
            if int(n) not in numbers:
                errors.append(f"labs/{lab}/{lab}.cpp:{line} (as made): names LAB {n}, which {readme} does not")
    return parsed.handout, errors


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="write nothing; fail on any difference")
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--solved", metavar="LAB", help="print LAB's solution without its markers and stand-ins")
    parser.add_argument("labs", nargs="*")
    args = parser.parse_args(argv)
    if args.solved:
        sys.stdout.write(solved(args.root, args.solved))
        return 0
    failed = False
    for lab in args.labs or labs_of(args.root):
        handout, errors = generate(args.root, lab)
        path = os.path.join("labs", lab, f"{lab}.cpp")
        for e in errors:
            print(e)
        if errors:
            print(f"{path}: neither compared nor written: the solution's markers are wrong")
            failed = True
            continue
        committed = None
        if os.path.isfile(os.path.join(args.root, path)):
            with open(os.path.join(args.root, path), encoding="utf-8", newline="") as f:
                committed = f.read()
        if committed == handout:
            continue
        if args.check:
            diff = difflib.unified_diff((committed or "").splitlines(keepends=True), handout.splitlines(keepends=True),
                                        f"{path} (committed)", f"{path} (made from the solution)", n=1)
            old, new = (committed or "").splitlines(), handout.splitlines()
            first = next((i for i, (x, y) in enumerate(zip(old, new)) if x != y), min(len(old), len(new))) + 1
            print(f"{path}:{first}: differs from what {os.path.basename(__file__)} makes of its solution "
                  f"(run labs/generate.py, or mend the solution):")
            sys.stdout.writelines(list(diff)[:40])
            failed = True
        else:
            os.makedirs(os.path.dirname(os.path.join(args.root, path)), exist_ok=True)
            with open(os.path.join(args.root, path), "w", encoding="utf-8", newline="") as f:
                f.write(handout)
            print(f"wrote {path}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
