#!/usr/bin/python3
"""A generated body that holds the cloth (the body-as-scanned issue): the demo
body in make-avatar's `handsonthighs` pose, the hands resting beside the
thighs as a customer stands in a scanner, wearing a dress whose skirt has to
pass between hand and thigh (pipelines/customers/demo-dress), through
`make fit` with no customer flags, at the small body resolution. The captured
pose is found held, make fit opens it by itself (AUTO_OPEN), and the fit of
the opened pose passes as a fit must."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CUSTOMER = os.path.join(ROOT, "pipelines", "customers", "demo-dress")
BIN = None


def load(path):
    with open(path) as f:
        return json.load(f)


class HeldFitTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="gp_held_fit_")
        cls.out = os.path.join(cls.dir, "out")
        cls.make = subprocess.run(
            ["make", "--no-print-directory", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
             f"CUSTOMER={CUSTOMER}", f"OUT={cls.out}", f"BIN={BIN}", "SIMULATE_QUIET=--quiet",
             "AVATAR_FLAGS=--poses apose,handsonthighs --resolution small"],
            cwd=ROOT, capture_output=True, text=True)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_make_fit_succeeds(self):
        self.assertEqual(self.make.returncode, 0, self.make.stdout[-4000:] + self.make.stderr[-4000:])

    def test_the_captured_pose_was_held_and_opened_by_itself(self):
        held = load(os.path.join(self.out, "fit-held", "report.json"))["held"]
        self.assertEqual(held["pose"], "handsonthighs")
        self.assertTrue(held["held_cloth"], held)
        place = held["held_cloth"][0]
        # The place is where a hand meets the skirt over the thigh: between
        # knee and waist, beside the body.
        self.assertGreater(place["position_m"][1], 0.55)
        self.assertLess(place["position_m"][1], 0.95)
        self.assertGreater(abs(place["position_m"][0]), 0.12)
        o = held["open_suggestion"]
        self.assertEqual(o["pose"], "handsonthighs")
        self.assertLess(o["largest_body_displacement_mm"], 60.0)
        with open(os.path.join(self.out, "auto-open.mk")) as f:
            self.assertIn("OPEN_POSE := handsonthighs", f.read())
        self.assertIn("fitting it opened", self.make.stdout)

    def test_verification_passes_at_every_key_pose_with_no_crossing(self):
        fit = load(os.path.join(self.out, "fit", "report.json"))
        v = fit["verification"]
        self.assertEqual(v["verdict"], "pass", json.dumps(v["key_poses"], indent=1)[:3000])
        self.assertEqual(len(v["key_poses"]), 3)
        for k in v["key_poses"]:
            with self.subTest(pose=k["pose"], key=k["key"]):
                self.assertTrue(k["settled"])
                c = k["crossings"]
                self.assertEqual(c["body_edge_crossings"] + c["cloth_edge_crossings"], 0)

    def test_pattern_and_sewn_garment(self):
        pattern = load(os.path.join(self.out, "pattern", "report.json"))
        self.assertEqual(pattern["rest_shape"]["turned_faces"], 0)
        self.assertLessEqual(pattern["summary"]["pieces"], 10)
        self.assertTrue(pattern["sewn_fit"]["checked"])
        self.assertEqual(pattern["sewn_fit"]["verdict"], "pass")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", required=True)
    args, rest = parser.parse_known_args()
    BIN = os.path.abspath(args.bin)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
