#!/usr/bin/env python3
"""Builds the lecture's slides (slides/README.md): the figures, the decks' Markdown with the code
included from the sources, and the offline HTML.

    build_deck.py expand DECK.md OUT.md [--root DIR]
        writes the deck with every `<!-- include: PATH#MARKER -->` line replaced by a code block: the
        lines between `// slide: MARKER` and `// end slide: MARKER` in PATH (relative to the project's
        root), dedented. Fails, naming the deck and line, when the file or a marker is missing, a
        marker is there twice, or a pair is unbalanced.
        A line `<!-- figure-missing: WHAT -->` becomes a visible placeholder box saying what is missing.
    build_deck.py figures --raster BIN --out DIR [--only NAME...]
        renders every figure of slides/figures.txt into DIR (the names the decks use).
    build_deck.py html --raster BIN --build DIR
        figures into DIR/figures, each deck expanded into DIR/md, then pandoc (reveal.js from
        slides/node_modules, MathML) into DIR/<deck>.html, self-contained; fails when an HTML file
        has a src or href that leaves the machine (check_offline).
    build_deck.py check-offline FILE.html...
        that check alone.

slides/figures.txt: one figure a line, `NAME: SCENE [raster render options]`; a scene that draws
frames (--frames N) gives NAME-0.png ... NAME-(N-1).png. `NAME: bench-error` is the run-time-
against-error plot of `raster bench error` (gnuplot; its timings differ from run to run, so no test
compares it).
"""
import argparse
from html import escape as html_escape
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
INCLUDE = re.compile(r"^\s*<!--\s*include:\s*(\S+?)#([A-Za-z0-9_-]+)\s*-->\s*$")
# A figure that no scene draws yet: shown as a dashed box that says what is missing.
MISSING = re.compile(r"^\s*<!--\s*figure-missing:\s*(.*?)\s*-->\s*$")
LANGUAGES = {".cpp": "cpp", ".hpp": "cpp", ".h": "cpp", ".py": "python", ".hlsl": "cpp"}
DECKS = [
    "01-participating-media",
    "02-ray-marching",
    "03-fog",
    "04-sprites-billboards",
    "05-particle-systems",
    "06-blending",
]
# A src or href that stays on the machine: in the document (#...), data: URIs, or a relative path.
LEAVES = re.compile(r"""(?:src|href)\s*=\s*["']?\s*((?:https?:|ftp:|wss?:)?//[^"'\s>]*)""", re.I)


LAB_LINE = re.compile(r"^\s*//(?:> .*|>$| BEGIN\b.*| END\b.*| STAND-IN\s*)$")


class DeckError(Exception):
    pass


def marked_lines(path, marker):
    """The lines between `// slide: marker` and `// end slide: marker` in path, dedented."""
    if not os.path.isfile(path):
        raise DeckError("%s: no such file" % path)
    lines = open(path, encoding="utf-8").read().split("\n")
    begin = re.compile(r"^\s*(?://|#)\s*slide:\s*%s\s*$" % re.escape(marker))
    end = re.compile(r"^\s*(?://|#)\s*end slide:\s*%s\s*$" % re.escape(marker))
    starts = [i for i, l in enumerate(lines) if begin.match(l)]
    ends = [i for i, l in enumerate(lines) if end.match(l)]
    if not starts:
        raise DeckError("%s: no marker `// slide: %s`" % (path, marker))
    if len(starts) > 1 or len(ends) > 1:
        raise DeckError("%s: marker %s appears more than once" % (path, marker))
    if not ends or ends[0] < starts[0]:
        raise DeckError("%s: `// slide: %s` without its `// end slide: %s` after it" % (path, marker, marker))
    # The answers as the solution has them: a lab's marker lines and the handout's stand-in lines
    # (labs/generate.py) left out.
    body = [l for l in lines[starts[0] + 1:ends[0]] if not LAB_LINE.match(l)]
    if not any(l.strip() for l in body):
        raise DeckError("%s: marker %s encloses nothing" % (path, marker))
    indent = min(len(l) - len(l.lstrip()) for l in body if l.strip())
    return [l[indent:] for l in body]


def expand(text, where, root=ROOT):
    """The deck's text with its include lines replaced by code blocks."""
    out = []
    for number, line in enumerate(text.split("\n"), 1):
        missing = MISSING.match(line)
        if missing:
            out.append('<div class="placeholder">Missing figure: %s</div>' % html_escape(missing.group(1)))
            continue
        m = INCLUDE.match(line)
        if not m:
            if "<!-- include" in line:
                raise DeckError("%s:%d: an include line must read <!-- include: PATH#MARKER -->" % (where, number))
            out.append(line)
            continue
        path, marker = m.group(1), m.group(2)
        try:
            body = marked_lines(os.path.join(root, path), marker)
        except DeckError as e:
            raise DeckError("%s:%d: %s" % (where, number, e))
        language = LANGUAGES.get(os.path.splitext(path)[1], "")
        out += ["```" + language] + body + ["```", "", "<p class=\"source\">%s</p>" % path]
    return "\n".join(out)


def read_figures():
    figures = []
    for number, line in enumerate(open(os.path.join(HERE, "figures.txt"), encoding="utf-8"), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        name, _, command = line.partition(":")
        words = command.split()
        if not words:
            raise DeckError("figures.txt:%d: no scene" % number)
        figures.append((name.strip(), words[0], words[1:]))
    return figures


def frame_count(options):
    return int(options[options.index("--frames") + 1]) if "--frames" in options else 0


def figure_files(name, options):
    """The PNG names a figure writes."""
    n = frame_count(options)
    return ["%s-%d.png" % (name, k) for k in range(n)] if n else [name + ".png"]


def render_figure(raster, name, scene, options, out):
    if scene == "bench-error":
        with tempfile.TemporaryDirectory() as scratch:
            run([raster, "bench", "error", "--out-dir", scratch] + options)
            plot = os.path.join(scratch, "error.png")
            if not os.path.isfile(plot):
                raise DeckError("raster bench error wrote no error.png (is gnuplot installed? .ci/setup with RASTER_WITH_SLIDES=1)")
            shutil.copyfile(plot, os.path.join(out, name + ".png"))
        return
    with tempfile.TemporaryDirectory() as scratch:
        run([raster, "render", scene, "--out-dir", scratch, "--threads", "2"] + options)
        n = frame_count(options)
        sources = ["%s_%04d.png" % (scene, k) for k in range(n)] if n else [scene + ".png"]
        for source, target in zip(sources, figure_files(name, options)):
            shutil.copyfile(os.path.join(scratch, source), os.path.join(out, target))


def run(command):
    done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        raise DeckError("%s failed (%d):\n%s" % (" ".join(command), done.returncode, done.stdout))


def figures(raster, out, only=None):
    os.makedirs(out, exist_ok=True)
    count = 0
    for name, scene, options in read_figures():
        if only and name not in only:
            continue
        render_figure(raster, name, scene, options, out)
        count += len(figure_files(name, options))
    return count


def check_offline(paths):
    """Every src and href of the files that points off the machine, as 'file: url'."""
    bad = []
    for path in paths:
        text = open(path, encoding="utf-8").read()
        bad += ["%s: %s" % (path, m.group(1)) for m in LEAVES.finditer(text)]
        # url(...) in inline CSS: a web font or image would be fetched too.
        bad += ["%s: url(%s)" % (path, m.group(1)) for m in re.finditer(r"url\(\s*[\"']?((?:https?:)?//[^)\"']*)", text)]
    return bad


def html(raster, build):
    reveal = os.path.join(HERE, "node_modules", "reveal.js")
    if not os.path.isfile(os.path.join(reveal, "dist", "reveal.js")):
        raise DeckError("no reveal.js in %s: run `npm ci` in slides/ (README, \"Slides\")" % reveal)
    if shutil.which("pandoc") is None:
        raise DeckError("pandoc not found: apt-get install pandoc (or RASTER_WITH_SLIDES=1 bash .ci/setup)")
    count = figures(raster, os.path.join(build, "figures"))
    print("slides: %d figures in %s" % (count, os.path.join(build, "figures")))
    os.makedirs(os.path.join(build, "md"), exist_ok=True)
    outputs = []
    for deck in DECKS:
        source = os.path.join(HERE, deck + ".md")
        expanded = os.path.join(build, "md", deck + ".md")
        with open(expanded, "w", encoding="utf-8") as f:
            f.write(expand(open(source, encoding="utf-8").read(), os.path.relpath(source, ROOT)))
        output = os.path.join(build, deck + ".html")
        run(["pandoc", expanded, "--standalone", "--self-contained", "--to", "revealjs", "--mathml",
             "--slide-level", "1", "--resource-path", build + os.pathsep + HERE,
             "--css", os.path.join(HERE, "slides.css"), "-V", "revealjs-url=" + reveal,
             "-V", "theme=white", "-V", "hash=true", "-V", "transition=none", "-V", "controls=true",
             "--metadata", "lang=en", "-o", output])
        outputs.append(output)
    bad = check_offline(outputs)
    if bad:
        raise DeckError("links that leave the machine:\n  " + "\n  ".join(bad))
    print("slides: %d decks in %s, no src or href leaves the machine" % (len(outputs), build))


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    e = sub.add_parser("expand")
    e.add_argument("deck"), e.add_argument("out"), e.add_argument("--root", default=ROOT)
    f = sub.add_parser("figures")
    f.add_argument("--raster", required=True), f.add_argument("--out", required=True)
    f.add_argument("--only", nargs="*")
    h = sub.add_parser("html")
    h.add_argument("--raster", required=True), h.add_argument("--build", required=True)
    c = sub.add_parser("check-offline")
    c.add_argument("files", nargs="+")
    a = parser.parse_args(argv)
    try:
        if a.command == "expand":
            text = expand(open(a.deck, encoding="utf-8").read(), a.deck, a.root)
            with open(a.out, "w", encoding="utf-8") as out:
                out.write(text)
        elif a.command == "figures":
            print("%d figures" % figures(a.raster, a.out, a.only))
        elif a.command == "html":
            html(a.raster, a.build)
        else:
            bad = check_offline(a.files)
            for b in bad:
                print("leaves the machine: " + b)
            return 1 if bad else 0
    except DeckError as err:
        print("build_deck: " + str(err), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
