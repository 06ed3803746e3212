#!/usr/bin/python3
"""Pipeline tests of `make fit` (pipelines/fit.mk) on a small generated
customer (testdata/customers/small-shirt): a second run does nothing, touching
the garment spec reruns exactly the dependent stages (the fit report last), a broken input stops the
pipeline at the right stage with its message and leaves earlier outputs
intact, two fresh runs give byte-identical files (timing.json aside), and a
stage's flags changed on the command line or in customer.mk rerun exactly
that stage and the ones after it."""
import argparse
import filecmp
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CUSTOMER = os.path.join(ROOT, "testdata", "customers", "small-shirt")
BIN = None


def fit(customer, out, expect_ok=True, variables=()):
    r = subprocess.run(["make", "--no-print-directory", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
                        f"CUSTOMER={customer}", f"OUT={out}", f"BIN={BIN}", *variables],
                       cwd=ROOT, capture_output=True, text=True)
    if expect_ok and r.returncode != 0:
        raise AssertionError(f"make fit failed ({r.returncode}):\n{r.stdout}\n{r.stderr}")
    stages = re.findall(r"^fit: ([a-z-]+)$", r.stdout, flags=re.M)
    return r, stages


def read(path):
    with open(path) as f:
        return f.read()


def tree_files(root):
    out = []
    for d, _, files in os.walk(root):
        for f in files:
            out.append(os.path.relpath(os.path.join(d, f), root))
    return sorted(out)


class PipelineTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="gp_pipeline_")
        cls.customer = os.path.join(cls.dir, "customer")
        shutil.copytree(CUSTOMER, cls.customer)
        cls.out = os.path.join(cls.dir, "out")
        cls.first, cls.first_stages = fit(cls.customer, cls.out)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_1_first_run_runs_every_stage(self):
        self.assertEqual(self.first_stages,
                         ["make-avatar", "register-check", "make-garment", "simulate-adapt", "export-rest",
                          "fit-report"])
        for stage in ("body", "poses", "garment", "fit", "pattern", "report"):
            self.assertTrue(os.path.isfile(os.path.join(self.out, stage, "report.json")), stage)
        self.assertIn("pattern.svg", self.first.stdout)
        self.assertEqual(self.first.stdout.strip().splitlines()[-1],
                         f"fit: report: {self.out}/report/index.html")

    def test_2_second_run_does_nothing(self):
        _, stages = fit(self.customer, self.out)
        self.assertEqual(stages, [])

    def test_3_touching_the_garment_spec_reruns_dependent_stages(self):
        body_report = os.path.join(self.out, "body", "report.json")
        before = os.path.getmtime(body_report)
        time.sleep(1.1)  # make compares modification times
        os.utime(os.path.join(self.customer, "garment-spec.json"))
        _, stages = fit(self.customer, self.out)
        self.assertEqual(stages, ["make-garment", "simulate-adapt", "export-rest", "fit-report"])
        self.assertEqual(os.path.getmtime(body_report), before)

    def test_4_broken_input_stops_at_its_stage(self):
        spec = os.path.join(self.customer, "garment-spec.json")
        good = read(spec)
        garment_before = read(os.path.join(self.out, "garment", "garment.json"))
        try:
            time.sleep(1.1)
            with open(spec, "w") as f:
                f.write(good.replace('"offset"', '"offsett"'))
            r, stages = fit(self.customer, self.out, expect_ok=False)
            self.assertNotEqual(r.returncode, 0)
            self.assertEqual(stages, ["make-garment"])
            self.assertIn("make-garment: error[spec]: unknown field 'offsett'", r.stderr)
            # Earlier and previous outputs are intact.
            self.assertEqual(read(os.path.join(self.out, "garment", "garment.json")), garment_before)
            for stage in ("body", "poses", "fit", "pattern", "report"):
                self.assertTrue(os.path.isfile(os.path.join(self.out, stage, "report.json")), stage)
            self.assertEqual([f for f in os.listdir(self.out) if f.startswith(".")], [])
        finally:
            time.sleep(1.1)
            with open(spec, "w") as f:
                f.write(good)

    def test_5_fresh_runs_are_byte_identical(self):
        # Reports name their input files, so the rerun uses the same paths.
        previous = os.path.join(self.dir, "previous")
        os.rename(self.out, previous)
        try:
            fit(self.customer, self.out)
            # Timings differ from run to run: timing.json, and the report's timing.js made of them.
            timed = ("timing.json", "timing.js")
            files = [f for f in tree_files(previous) if os.path.basename(f) not in timed]
            self.assertEqual(files, [f for f in tree_files(self.out) if os.path.basename(f) not in timed])
            differ = [f for f in files
                      if not filecmp.cmp(os.path.join(previous, f), os.path.join(self.out, f), shallow=False)]
            self.assertEqual(differ, [])
        finally:
            shutil.rmtree(previous, ignore_errors=True)

    def test_6_flags_on_the_command_line_rerun_their_stage(self):
        after_sim = ["simulate-adapt", "export-rest", "fit-report"]
        _, stages = fit(self.customer, self.out, variables=["SIMULATE_FLAGS=--settle-max-steps 100"])
        self.assertEqual(stages, after_sim)
        with open(os.path.join(self.out, "fit", "report.json")) as f:
            self.assertEqual(json.load(f)["options"]["settle_max_steps"], 100)
        _, stages = fit(self.customer, self.out, variables=["SIMULATE_FLAGS=--settle-max-steps 100"])
        self.assertEqual(stages, [])
        # Back to customer.mk's flags: the fit is made with them again.
        _, stages = fit(self.customer, self.out)
        self.assertEqual(stages, after_sim)
        with open(os.path.join(self.out, "fit", "report.json")) as f:
            self.assertEqual(json.load(f)["options"]["settle_max_steps"], 120)

    def test_7_flags_changed_in_customer_mk_rerun_their_stage(self):
        mk = os.path.join(self.customer, "customer.mk")
        good = read(mk)
        try:
            with open(mk, "a") as f:
                # The default: another string, the same pattern (added to
                # customer.mk's own flags, which bound the sewn drape).
                f.write("EXPORT_FLAGS += --max-rounds 16\n")
            _, stages = fit(self.customer, self.out)
            self.assertEqual(stages, ["export-rest", "fit-report"])
            _, stages = fit(self.customer, self.out)
            self.assertEqual(stages, [])
        finally:
            with open(mk, "w") as f:
                f.write(good)
        _, stages = fit(self.customer, self.out)
        self.assertEqual(stages, ["export-rest", "fit-report"])

    def test_8_an_opened_pose_replaces_the_captured_one(self):
        out = os.path.join(self.dir, "opened-out")
        target = os.path.join(out, "poses", "report.json")
        opened = ["OPEN_POSE=apose", "OPEN_TOWARD=tpose", "OPEN_STEPS=10"]
        r, stages = fit(self.customer, out, variables=opened + [target])
        self.assertEqual(stages, ["make-avatar", "interp-poses", "register-check"])
        manifest = json.loads(read(os.path.join(out, "poses", "poses.json")))
        self.assertEqual([p["name"] for p in manifest["poses"]], ["apose", "tpose"])
        a, t = read_ply_vertices(os.path.join(out, "body", "apose.ply")), read_ply_vertices(os.path.join(out, "body", "tpose.ply"))
        o = read_ply_vertices(os.path.join(out, "opened", "poses", "apose.ply"))
        # The arms, which move most from A to T, have gone about a tenth of the way.
        a_to_t = [sum((p - q) ** 2 for p, q in zip(u, v)) ** 0.5 for u, v in zip(a, t)]
        a_to_o = [sum((p - q) ** 2 for p, q in zip(u, v)) ** 0.5 for u, v in zip(a, o)]
        far = max(range(len(a)), key=lambda i: a_to_t[i])
        self.assertGreater(a_to_o[far], 0.05 * a_to_t[far])
        self.assertLess(a_to_o[far], 0.2 * a_to_t[far])
        self.assertTrue(filecmp.cmp(os.path.join(out, "opened", "poses", "tpose.ply"),
                                    os.path.join(out, "body", "tpose.ply"), shallow=False))
        _, stages = fit(self.customer, out, variables=opened + [target])
        self.assertEqual(stages, [])
        # Dropping the opened pose registers the captured ones again.
        _, stages = fit(self.customer, out, variables=[target])
        self.assertEqual(stages, ["register-check"])
        manifest = json.loads(read(os.path.join(out, "poses", "poses.json")))
        self.assertTrue(all("/body/" in p["source"] for p in manifest["poses"]), manifest["poses"])
        # A pose the customer does not have: interp-poses names it, and nothing is left half made.
        bad = os.path.join(self.dir, "opened-bad")
        r, _ = fit(self.customer, bad, expect_ok=False, variables=["OPEN_POSE=sitting", "OPEN_TOWARD=tpose",
                                                                   os.path.join(bad, "poses", "report.json")])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("unknown pose 'sitting'", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(bad, "opened")))
        self.assertFalse(os.path.exists(os.path.join(bad, "opened.tmp")))
        r, _ = fit(self.customer, bad, expect_ok=False, variables=["OPEN_POSE=apose",
                                                                   os.path.join(bad, "poses", "report.json")])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("OPEN_POSE=apose needs OPEN_TOWARD", r.stderr)


def read_ply_vertices(path):
    """Vertex positions of a binary little-endian PLY whose vertices start
    with x, y, z as doubles or floats (what the stages write)."""
    import struct
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    count, props = 0, []
    for line in header:
        w = line.split()
        if w[:2] == ["element", "vertex"]:
            count, props = int(w[2]), []
        elif w and w[0] == "element":
            break
        elif w and w[0] == "property" and count:
            props.append(w[1])
    size = {"double": 8, "float": 4}
    fmt = "<" + "".join("d" if p == "double" else "f" for p in props)
    stride = sum(size[p] for p in props)
    return [struct.unpack_from(fmt, data, end + i * stride)[:3] for i in range(count)]


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("--bin", required=True)
    args, rest = p.parse_known_args()
    BIN = os.path.abspath(args.bin)
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
