#!/usr/bin/python3
"""The golden comparison fails when an output is perturbed beyond its
tolerance and passes within it (scripts/golden.py, on files made here)."""
import json
import os
import shutil
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
import golden  # noqa: E402
from test_meshdiff import grid, write  # noqa: E402


class GoldenTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="golden_test_")
        self.saved = golden.GOLDEN
        golden.GOLDEN = os.path.join(self.dir, "golden")
        self.out = os.path.join(self.dir, "out")
        os.makedirs(os.path.join(self.out, "fit"))
        self.pts, self.tris = grid(8)
        write(os.path.join(self.out, "fit", "rest.ply"), self.pts, self.tris)
        with open(os.path.join(self.out, "fit", "report.json"), "w") as f:
            json.dump({"key_poses": [{"max_stretch": 1.1}]}, f)
        self.case = {"meshes": [("fit/rest.ply", 1e-3, 1e-3)],
                     "figures": [("fit/report.json", ["key_poses", 0, "max_stretch"], 1e-3, None)]}
        golden.update_case("t", self.case, self.out)

    def tearDown(self):
        golden.GOLDEN = self.saved
        shutil.rmtree(self.dir, ignore_errors=True)

    def test_unchanged_outputs_pass(self):
        self.assertEqual(golden.compare_case("t", self.case, self.out), [])

    def test_perturbed_mesh_fails(self):
        moved = self.pts.copy()
        moved[5, 1] += 0.01  # 1 cm on a 1.4 m diagonal: 7e-3 of it, over 1e-3
        write(os.path.join(self.out, "fit", "rest.ply"), moved, self.tris)
        failures = golden.compare_case("t", self.case, self.out)
        self.assertEqual(len(failures), 1)
        self.assertIn("fit/rest.ply differs", failures[0])

    def test_perturbed_figure_fails(self):
        with open(os.path.join(self.out, "fit", "report.json"), "w") as f:
            json.dump({"key_poses": [{"max_stretch": 1.102}]}, f)
        failures = golden.compare_case("t", self.case, self.out)
        self.assertEqual(len(failures), 1)
        self.assertIn("max_stretch is 1.102", failures[0])


if __name__ == "__main__":
    unittest.main()
