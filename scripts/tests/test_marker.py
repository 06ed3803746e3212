#!/usr/bin/python3
"""make-marker on pieces made here: an overlap check independent of the
tool's (matplotlib's point-in-polygon on a fine grid over every pair's common
box), every piece inside the fabric's width, the grain kept (0 or 180
degrees), mirrored pairs placed once mirrored, the length and utilisation
recomputed from the placements, the same marker for the same seed and
budget, and a bad input's exit code.

usage: test_marker.py --bin build/bin
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from matplotlib.path import Path

BIN = "build/bin"


def area(poly):
    return 0.5 * abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(poly, poly[1:] + poly[:1])))


def overlap_area(a, b, samples=160):
    """Area shared by two polygons, estimated on a grid over their common box."""
    ax, ay = np.array(a).T
    bx, by = np.array(b).T
    x0, x1 = max(ax.min(), bx.min()), min(ax.max(), bx.max())
    y0, y1 = max(ay.min(), by.min()), min(ay.max(), by.max())
    if x1 <= x0 or y1 <= y0:
        return 0.0
    xs = np.linspace(x0, x1, samples + 2)[1:-1]
    ys = np.linspace(y0, y1, samples + 2)[1:-1]
    pts = np.array([(x, y) for y in ys for x in xs])
    both = Path(a).contains_points(pts) & Path(b).contains_points(pts)
    return both.sum() * (x1 - x0) * (y1 - y0) / len(pts)


def pieces():
    """Deterministic mix: rectangles, L shapes, triangles, a mirrored pair."""
    out = []
    rng = np.random.default_rng(7)
    for k in range(6):
        w, h = rng.uniform(0.15, 0.45), rng.uniform(0.1, 0.35)
        out.append({"name": "rect %d" % k, "quantity": 1, "outline": [[0, 0], [w, 0], [w, h], [0, h]]})
    for k in range(3):
        s = rng.uniform(0.2, 0.4)
        out.append({"name": "ell %d" % k, "quantity": 2, "mirrored_pairs": True,
                    "outline": [[0, 0], [s, 0], [s, 0.3 * s], [0.3 * s, 0.3 * s], [0.3 * s, s], [0, s]]})
    for k in range(4):
        s = rng.uniform(0.15, 0.3)
        out.append({"name": "tri %d" % k, "quantity": 1, "outline": [[0, 0], [s, 0.1 * s], [0.2 * s, 0.9 * s]]})
    return {"schema": "marker-pieces/1", "units": "m", "fabric_width": 0.9, "pieces": out}


def run(args):
    return subprocess.run([os.path.join(BIN, "make-marker")] + args, capture_output=True, text=True)


class MarkerTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="marker-test-")
        cls.spec = os.path.join(cls.tmp, "pieces.json")
        json.dump(pieces(), open(cls.spec, "w"))
        r = run([cls.spec, "--time-budget", "0.5", "--out", os.path.join(cls.tmp, "a"), "-q"])
        assert r.returncode == 0, r.stderr
        cls.report = json.load(open(os.path.join(cls.tmp, "a", "report.json")))

    def test_no_overlap_inside_width(self):
        rep = self.report
        width = rep["fabric_width"]
        self.assertEqual(width, 0.9)
        pl = rep["placements"]
        self.assertEqual(len(pl), 6 + 6 + 4)
        for p in pl:
            ys = [q[1] for q in p["outline"]]
            xs = [q[0] for q in p["outline"]]
            self.assertGreaterEqual(min(ys), -1e-9)
            self.assertLessEqual(max(ys), width + 1e-9)
            self.assertGreaterEqual(min(xs), -1e-9)
            self.assertIn(p["rotation_deg"], (0, 180))
        worst = 0.0
        for i in range(len(pl)):
            for j in range(i + 1, len(pl)):
                a, b = pl[i]["outline"], pl[j]["outline"]
                worst = max(worst, overlap_area(a, b) / min(area(a), area(b)))
        # The grid estimate of a touching pair stays at zero; a real overlap
        # of one raster cell (3 mm) along a 15 cm side is about 2 % of a piece.
        self.assertLess(worst, 1e-3)
        self.assertEqual(rep["overlapping_pairs"], 0)
        self.assertTrue(rep["inside_width"])

    def test_figures_from_placements(self):
        rep = self.report
        pl = rep["placements"]
        length = max(q[0] for p in pl for q in p["outline"])
        self.assertAlmostEqual(rep["length"], length, places=9)
        total = sum(area(p["outline"]) for p in pl)
        self.assertAlmostEqual(rep["utilisation"], total / (rep["fabric_width"] * length), places=9)
        self.assertLessEqual(rep["length"], rep["largest_first_length"] + 1e-12)
        # Better than a shelf of bounding boxes would need: the area bound.
        self.assertGreater(rep["utilisation"], 0.5)

    def test_mirrored_pairs(self):
        pl = self.report["placements"]
        for k in range(3):
            copies = sorted((p["copy"], p["mirrored"]) for p in pl if p["piece"] == "ell %d" % k)
            self.assertEqual(copies, [(0, False), (1, True)])
            # The mirrored copy's outline is the mirror image: same area, reversed turn.
            ells = [p for p in pl if p["piece"] == "ell %d" % k]
            self.assertAlmostEqual(area(ells[0]["outline"]), area(ells[1]["outline"]), places=12)

    def test_deterministic(self):
        r = run([self.spec, "--time-budget", "0.5", "--out", os.path.join(self.tmp, "b"), "-q"])
        self.assertEqual(r.returncode, 0, r.stderr)
        for f in ("report.json", "marker.svg", "marker.pdf"):
            self.assertEqual(open(os.path.join(self.tmp, "a", f), "rb").read(),
                             open(os.path.join(self.tmp, "b", f), "rb").read(), f)

    def test_too_wide_and_bad_spec(self):
        r = run([self.spec, "--width", "0.1", "--out", os.path.join(self.tmp, "narrow"), "-q"])
        self.assertEqual(r.returncode, 5, r.stderr)
        self.assertIn("make-marker: error[geometry]", r.stderr)
        bad = os.path.join(self.tmp, "bad.json")
        doc = pieces()
        doc["pieces"][0]["quantiti"] = 2
        json.dump(doc, open(bad, "w"))
        r = run([bad, "--out", os.path.join(self.tmp, "bad"), "-q"])
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("quantiti", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "bad")))


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=BIN)
    args, rest = ap.parse_known_args()
    BIN = args.bin
    unittest.main(argv=[sys.argv[0]] + rest)
