#!/usr/bin/env python3
"""Re-renders every figure of the slides (slides/figures.txt) and compares it with the committed one
in slides/figures/ through the project's image comparison (slides_image_diff, raster/image_compare.hpp):
a change that alters a figure fails here until the figure is regenerated on purpose
(`python3 slides/build_deck.py figures --raster build/bin/raster --out slides/figures`).

    slides_figures_test.py SOURCE_DIR RASTER SLIDES_IMAGE_DIFF

The run-time-against-error plot (bench-error) is timings, different on every run: it is named as not
compared, and only its committed file is required.
"""
import os
import subprocess
import sys
import tempfile


def main(source_dir, raster, image_diff):
    sys.path.insert(0, os.path.join(source_dir, "slides"))
    import build_deck
    committed = os.path.join(source_dir, "slides", "figures")
    failures, pairs, names = [], [], []
    with tempfile.TemporaryDirectory() as scratch:
        for name, scene, options in build_deck.read_figures():
            files = build_deck.figure_files(name, options)
            for f in files:
                if not os.path.isfile(os.path.join(committed, f)):
                    failures.append("slides/figures/%s is not committed" % f)
            if scene == "bench-error":
                print("not compared: %s (raster bench error's timings change from run to run)" % name)
                continue
            build_deck.render_figure(raster, name, scene, options, scratch)
            names.append(name)
            pairs += [(os.path.join(committed, f), os.path.join(scratch, f)) for f in files
                      if os.path.isfile(os.path.join(committed, f))]
        done = subprocess.run([image_diff] + [p for pair in pairs for p in pair], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True)
        print(done.stdout, end="")
        if done.returncode != 0:
            failures.append("rendered figures differ from the committed ones (above)")
    for f in failures:
        print("FAIL " + f)
    if not pairs:
        print("FAIL no figure compared")
        return 1
    print("slides_figures: %d figures (%d files) re-rendered and compared: %s" %
          (len(names), len(pairs), "FAIL" if failures else "all identical"))
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(*sys.argv[1:]))
