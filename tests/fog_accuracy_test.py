#!/usr/bin/env python3
"""raster bench fog-accuracy on the grid's every other value (--quick, a tenth of a second).

Its CSV holds every quantity's forms; raster's have no NaN, no misplaced infinity and stay within
8 ulps times (1 + the condition number) everywhere, while the lecture's direct forms give NaN (0/0 at
sigma = 0) and the 1e-5 floor loses thin fog by millions of ulps: the comparison can fail both ways.

    python3 tests/fog_accuracy_test.py build/bin/raster
"""

import csv
import os
import subprocess
import sys
import tempfile
import unittest

RASTER = None


class FogAccuracy(unittest.TestCase):
    def test_quick_grid(self):
        with tempfile.TemporaryDirectory() as out:
            run = subprocess.run([RASTER, "bench", "fog-accuracy", "--quick", "--out", out],
                                 capture_output=True, text=True, timeout=60, check=False)
            self.assertEqual(run.returncode, 0, run.stderr)
            with open(os.path.join(out, "fog-accuracy.csv"), newline="") as f:
                rows = {(r["quantity"], r["form"]): r for r in csv.DictReader(f)}
            with open(os.path.join(out, "fog-accuracy-points.csv"), newline="") as f:
                panels = {r["panel"] for r in csv.DictReader(f)}
        self.assertEqual(panels, {"homogeneous", "tau-sweep", "height-fog"})
        for quantity in ("homogeneous L", "height-fog tau", "height-fog L"):
            r = rows[(quantity, "raster")]
            self.assertGreater(int(r["cases"]), 50, quantity)
            self.assertEqual(int(r["nan"]), 0, quantity)
            self.assertEqual(int(r["infinite"]), 0, quantity)
            self.assertLessEqual(float(r["max_ulp_per_condition"]), 8.0, quantity)
            self.assertEqual(float(r["share_within_8_ulp_condition"]), 1.0, quantity)
        self.assertGreater(int(rows[("homogeneous L", "lecture")]["nan"]), 0)
        self.assertEqual(int(rows[("homogeneous L", "floor")]["nan"]), 0)
        self.assertGreater(float(rows[("homogeneous L", "floor")]["max_ulp"]), 1e6)
        self.assertGreater(int(rows[("height-fog L", "slide")]["nan"]), 0)


if __name__ == "__main__":
    RASTER = sys.argv.pop(1)
    unittest.main()
