#!/usr/bin/env python3
"""The slide decks' sources (slides/*.md, slides/build_deck.py):

  - every deck expands: each `<!-- include: PATH#MARKER -->` finds its marker pair in PATH;
  - the preprocessor fails on a missing file, a missing marker, an unbalanced or a doubled pair;
  - every figure a deck shows is one that slides/figures.txt renders, and is committed;
  - the placeholders for figures that no scene draws yet are listed (none today);
  - the offline check finds a src or href that leaves the machine and passes local ones.

    slides_decks_test.py SOURCE_DIR
"""
import os
import re
import sys
import tempfile


def main(source_dir):
    sys.path.insert(0, os.path.join(source_dir, "slides"))
    import build_deck
    failures = []
    rendered = set()
    for name, _, options in build_deck.read_figures():
        rendered.update(build_deck.figure_files(name, options))
    includes = shown = 0
    placeholders = []
    for deck in build_deck.DECKS:
        path = os.path.join(source_dir, "slides", deck + ".md")
        text = open(path, encoding="utf-8").read()
        try:
            expanded = build_deck.expand(text, path, source_dir)
            includes += sum(1 for line in text.split("\n") if build_deck.INCLUDE.match(line))
        except build_deck.DeckError as e:
            failures.append(str(e))
            continue
        for figure in re.findall(r"\]\(figures/([^)\s]+)\)", expanded):
            shown += 1
            if figure not in rendered:
                failures.append("%s shows figures/%s, which figures.txt does not render" % (deck, figure))
            if not os.path.isfile(os.path.join(source_dir, "slides", "figures", figure)):
                failures.append("%s shows figures/%s, which is not committed" % (deck, figure))
        for what in re.findall(r'<div class="placeholder">Missing figure: (.*?)</div>', expanded):
            placeholders.append("%s: %s" % (deck, what))
    with tempfile.TemporaryDirectory() as d:
        src = os.path.join(d, "a.cpp")
        with open(src, "w") as f:
            f.write("int a;\n// slide: good\nint b;\n// end slide: good\n// slide: open\nint c;\n"
                    "// slide: twice\n// end slide: twice\n// slide: twice\n// end slide: twice\n")
        cases = {"good": None, "absent": "no marker", "open": "without its", "twice": "more than once"}
        for marker, expected in cases.items():
            try:
                out = build_deck.expand("<!-- include: a.cpp#%s -->" % marker, "t.md", d)
                if expected is not None:
                    failures.append("marker %s: expanded, but should fail with '%s'" % (marker, expected))
                elif "int b;" not in out or "slide:" in out:
                    failures.append("marker good: expanded to %r" % out)
            except build_deck.DeckError as e:
                if expected is None or expected not in str(e):
                    failures.append("marker %s: %s" % (marker, e))
        try:
            build_deck.expand("<!-- include: missing.cpp#x -->", "t.md", d)
            failures.append("a missing file expanded")
        except build_deck.DeckError:
            pass
        box = build_deck.expand("<!-- figure-missing: no scene draws X -->", "t.md", d)
        if box != '<div class="placeholder">Missing figure: no scene draws X</div>':
            failures.append("a figure-missing line expanded to %r, not a placeholder box" % box)
        html = os.path.join(d, "a.html")
        with open(html, "w") as f:
            f.write('<img src="data:image/png;base64,AA"><a href="#/3">x</a><img src="figures/a.png">'
                    '<script src="https://cdn.example.org/reveal.js"></script>'
                    '<link href="//fonts.example.org/css"><style>@font-face{src:url(http://x.org/f.woff)}</style>')
        bad = build_deck.check_offline([html])
        if len(bad) != 3:
            failures.append("check_offline found %d links off the machine, not 3: %s" % (len(bad), bad))
    for p in placeholders:
        print("placeholder left (a figure no scene draws yet): " + p)
    for f in failures:
        print("FAIL " + f)
    print("slides_decks: %d placeholders left" % len(placeholders))
    print("slides_decks: %d decks, %d code includes, %d figures shown: %s" %
          (len(build_deck.DECKS), includes, shown, "FAIL" if failures else "all good"))
    return 1 if failures or includes == 0 or shown == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
