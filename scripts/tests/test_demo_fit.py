#!/usr/bin/python3
"""The demo customer (a generated 1.70 m body, a shirt of about 1,100
vertices, A -> T -> arms up -> A) through `make fit`, judged as the
rest-shape issue asks: the verification (the final rest shape simulated
afresh) passes at every key pose with no crossing, and export-rest's
rest-shape figures show no tuck. The paper's rule on the same inputs makes
the cones that ours does not."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CUSTOMER = os.path.join(ROOT, "pipelines", "customers", "demo")
BIN = None


def load(path):
    with open(path) as f:
        return json.load(f)


def run(cmd):
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    return r


class DemoFitTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="gp_demo_fit_")
        cls.out = os.path.join(cls.dir, "out")
        cls.make = run(["make", "--no-print-directory", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
                        f"CUSTOMER={CUSTOMER}", f"OUT={cls.out}", f"BIN={BIN}", "SIMULATE_QUIET=--quiet"])
        cls.fit = load(os.path.join(cls.out, "fit", "report.json"))
        cls.rest = load(os.path.join(cls.out, "pattern", "report.json"))["rest_shape"]

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_make_fit_succeeds(self):
        self.assertEqual(self.make.returncode, 0, self.make.stdout + self.make.stderr)

    def test_verification_passes_at_every_key_pose(self):
        v = self.fit["verification"]
        self.assertEqual(v["verdict"], "pass", json.dumps(v["key_poses"], indent=1)[:3000])
        self.assertEqual(len(v["key_poses"]), 4)
        for k in v["key_poses"]:
            with self.subTest(pose=k["pose"], key=k["key"]):
                self.assertLess(k["area_fraction_above_limit"], 0.01)
                self.assertLessEqual(k["p99_stretch"], 1.12)
                self.assertLessEqual(k["deepest_penetration_m"], 0.002)
                c = k["crossings"]
                self.assertEqual(c["body_edge_crossings"] + c["cloth_edge_crossings"], 0)

    def test_rest_shape_has_no_tucks(self):
        r = self.rest
        # Measured: growth x1.062, 0 turned, 17 cones (design 18), 28.1 rad (design 27.6).
        self.assertGreater(r["area_growth"], 1.01)  # it did adapt
        self.assertLess(r["area_growth"], 1.20)
        self.assertEqual(r["turned_faces"], 0)
        self.assertLessEqual(r["cone_points"], r["cone_points_design"] + 5)
        self.assertLessEqual(r["abs_angle_defect_sum_rad"], 1.3 * r["abs_angle_defect_sum_design_rad"])

    def test_the_papers_rule_makes_cones(self):
        # The paper's adaptation rule (clip every 8 steps throughout, plain
        # ARAP) on the project's cloth. Measured: 63 cones and 43.3 rad
        # against ours 17 and 28.7 (before the softer compression).
        paper = os.path.join(self.dir, "paper")
        garment = os.path.join(self.out, "garment", "garment.json")
        sim = run([os.path.join(BIN, "simulate-adapt"), "--poses", os.path.join(self.out, "poses", "poses.json"),
                   "--motion", os.path.join(CUSTOMER, "motion.json"), "--garment", garment,
                   "--adapt-during-transitions", "--smoothing-length", "0", "--adapt-rounds", "1",
                   "--margin", "0", "--hysteresis", "0", "--no-verify", "--out", os.path.join(paper, "fit"), "--quiet"])
        self.assertEqual(sim.returncode, 0, sim.stderr)
        exp = run([os.path.join(BIN, "export-rest"), os.path.join(paper, "fit", "rest.ply"), "--garment", garment,
                   "--out", os.path.join(paper, "pattern"), "--quiet"])
        self.assertEqual(exp.returncode, 0, exp.stderr)
        theirs = load(os.path.join(paper, "pattern", "report.json"))["rest_shape"]
        self.assertGreater(theirs["cone_points"], self.rest["cone_points"] + 10)
        self.assertGreater(theirs["abs_angle_defect_sum_rad"], self.rest["abs_angle_defect_sum_rad"])


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", required=True)
    args, rest = parser.parse_known_args()
    BIN = os.path.abspath(args.bin)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
