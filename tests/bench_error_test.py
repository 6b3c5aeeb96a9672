#!/usr/bin/env python3
"""raster bench error with a few rays, without gnuplot on the PATH: it says so and still writes
error.csv, whose rows have finite positive times, whose exponential and midpoint errors fall as the
steps grow, whose Euler error at 4 steps (mu*ds up to 3 on the homogeneous rays) is large, and whose
Pareto marks hold (no marked row is beaten in time and max error by a row of its medium and quantity).
  python3 tests/bench_error_test.py build/bin/raster"""
import csv
import math
import os
import subprocess
import sys
import tempfile


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def main():
    raster = sys.argv[1]
    with tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, PATH=os.path.join(out, "no-tools"))  # no gnuplot
        run = subprocess.run([raster, "bench", "error", "--rays", "3", "--seed", "5", "--out-dir", out],
                             capture_output=True, text=True, env=env, timeout=60)
        print(run.stdout[-3000:], run.stderr)
        if run.returncode != 0:
            fail(f"exit status {run.returncode}")
        if "gnuplot not found" not in run.stdout:
            fail("no word that gnuplot is missing")
        if os.path.exists(os.path.join(out, "error.png")):
            fail("error.png without gnuplot")
        with open(os.path.join(out, "error.csv")) as f:
            rows = list(csv.DictReader(f))
    if len(rows) < 60:
        fail(f"only {len(rows)} rows")
    for r in rows:
        t = float(r["time_us"])
        if not (math.isfinite(t) and t > 0):
            fail(f"time {t} in {r}")
        if r["integrator"] == "scene-march" and r["knob"].startswith("grid=") and "same-bits-as-none" not in r["knob"]:
            fail(f"grid skipping changed the march: {r}")

    def curve(medium, integrator):
        return [(int(r["steps"]), float(r["max_err"])) for r in rows
                if r["medium"] == medium and r["integrator"] == integrator and r["knob"] == "-"]

    for medium in ("smooth", "metaball"):
        for integrator in ("exponential", "midpoint"):
            c = curve(medium, integrator)
            if len(c) < 8 or not c[-1][1] < c[0][1] / 100:
                fail(f"{medium} {integrator}: the error does not fall with the steps: {c}")
            if medium == "smooth" and any(b[1] > a[1] * 1.01 for a, b in zip(c, c[1:])):
                fail(f"smooth {integrator}: the error grows with the steps somewhere: {c}")
    euler4 = dict(curve("homogeneous", "euler"))[4]
    exact4 = dict(curve("homogeneous", "exponential"))[4]
    if not (euler4 > 0.1 and exact4 < 1e-12):
        fail(f"homogeneous at 4 steps: euler {euler4} (expected > 0.1), exponential {exact4} (expected exact)")
    for a in rows:
        if a["pareto"] != "1":
            continue
        for b in rows:
            if b is a or (b["medium"], b["quantity"]) != (a["medium"], a["quantity"]):
                continue
            ta, ea, tb, eb = (float(a["time_us"]), float(a["max_err"]), float(b["time_us"]), float(b["max_err"]))
            if tb <= ta and eb <= ea and (tb < ta or eb < ea):
                fail(f"marked row {a} is dominated by {b}")
    print(f"ok: {len(rows)} rows; homogeneous euler at 4 steps {euler4:.3g}")


main()
