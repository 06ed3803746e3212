#!/usr/bin/python3
"""The Slurm batch (scripts/fit_batch.py) on a real single-node Slurm started
for the test (scripts/tests/local_slurm.py): three small generated customers,
one with a broken garment spec, as one job array and a summary job.

Asserts that the two good fits complete and the broken one is reported with
its stage (make-garment) and exit code (4, spec); that Slurm's states agree;
that the summary's figures are the customers' own reports'; and that
resubmitting the same batch runs no stage for the two completed customers
(and the broken one's failing stage again). Exits 77 (CTest's skip) where
the daemons cannot start for want of root; as root (CI) it runs."""
import argparse
import datetime
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import fit_batch  # noqa: E402
import local_slurm  # noqa: E402

SMALL_SHIRT = os.path.join(ROOT, "testdata", "customers", "small-shirt")
SKIP = 77
BIN = None


def make_customers(folder):
    """Three customers from the small generated shirt: as it is, on a body
    with other girths, and with a misspelt field in its garment spec."""
    customers = {}
    for name in ("ada", "bea", "cid"):
        c = os.path.join(folder, name)
        shutil.copytree(SMALL_SHIRT, c)
        with open(os.path.join(c, "customer.mk"), "a") as f:
            f.write("NO_SEW_CHECK := 1\n")  # the pattern's own check simulates once more: not needed here
        customers[name] = c
    avatar = os.path.join(customers["bea"], "avatar.json")
    with open(avatar) as f:
        spec = json.load(f)
    spec["measurements"].update(chest=0.95, waist=0.79, hip=1.0)
    with open(avatar, "w") as f:
        json.dump(spec, f, indent=2)
    garment = os.path.join(customers["cid"], "garment-spec.json")
    with open(garment) as f:
        text = f.read()
    with open(garment, "w") as f:
        f.write(text.replace('"offset"', '"offsett"'))
    return customers


def submit(batch, customers):
    """The batch submitted and waited for; its time from submission to the
    summary, as the batch's own files record it (whole seconds: sbatch
    --wait polls at growing intervals and returns later)."""
    r = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "fit_batch.py"), "submit",
                        "--batch", batch, "--bin", BIN, "--wait", *customers],
                       capture_output=True, text=True)
    seconds = None
    try:
        with open(os.path.join(batch, "jobs.json")) as f:
            submitted = json.load(f)["submitted"]
        with open(os.path.join(batch, "summary.json")) as f:
            written = json.load(f)["written"]
        stamp = "%Y-%m-%dT%H:%M:%SZ"
        seconds = (datetime.datetime.strptime(written, stamp) - datetime.datetime.strptime(submitted, stamp)).seconds
    except (OSError, KeyError, ValueError):
        pass
    return r, seconds


class SlurmBatchTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="gp_slurm_")
        cls.slurm = local_slurm.LocalSlurm(os.path.join(cls.dir, "slurm"))
        try:
            cls.slurm.__enter__()
            cls.customers = make_customers(os.path.join(cls.dir, "customers"))
            cls.batch = os.path.join(cls.dir, "batch")
            cls.first, seconds = submit(cls.batch, list(cls.customers.values()))
            print(f"\nslurm_batch: Slurm {local_slurm.version()}; first batch (3 customers): "
                  f"{seconds} s from submission to summary", file=sys.stderr)
            with open(os.path.join(cls.batch, "summary.json")) as f:
                cls.summary = json.load(f)
            cls.rows = {r["name"]: r for r in cls.summary["rows"]}
            print("slurm_batch: tasks " + ", ".join(f"{r['name']} {r['elapsed_s']} s" for r in cls.summary["rows"]),
                  file=sys.stderr)
        except BaseException:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        cls.slurm.__exit__(None, None, None)
        shutil.rmtree(cls.dir, ignore_errors=True)
        running = cls.slurm.running()
        if running:
            raise AssertionError(f"still running after the test: {', '.join(running)}")

    def test_1_two_fits_complete_and_the_broken_one_fails_at_its_stage(self):
        msg = f"{self.first.stdout}\n{self.first.stderr}"
        self.assertEqual(self.first.returncode, 1, msg)  # not every customer succeeded
        self.assertEqual(self.summary["schema"], "fit-batch-summary/1")
        self.assertEqual(self.summary["counts"], {"completed": 2, "failed": 1})
        self.assertFalse(self.summary["all_succeeded"])
        for name in ("ada", "bea"):
            row = self.rows[name]
            self.assertEqual(row["state"], "completed", msg)
            self.assertIsNone(row["failing_stage"])
            self.assertEqual(row["exit_code"], 0)
            self.assertEqual(row["stages_run"], ["make-avatar", "register-check", "make-garment", "simulate-adapt",
                                                 "export-rest", "fit-report"])
            self.assertEqual(row["report"], os.path.relpath(
                os.path.join(self.customers[name], "out", "report", "index.html"), self.batch))
            self.assertTrue(os.path.isfile(os.path.join(self.batch, row["report"])))
        cid = self.rows["cid"]
        self.assertEqual(cid["state"], "failed")
        self.assertEqual(cid["failing_stage"], "make-garment")
        self.assertEqual(cid["exit_code"], 4)
        self.assertEqual(cid["category"], "spec")
        self.assertIn("make-garment: error[spec]: unknown field 'offsett'", cid["error"])
        self.assertEqual(cid["stages_run"], ["make-avatar", "register-check", "make-garment"])
        self.assertEqual(cid["figures"], {})
        self.assertIsNone(cid["report"])
        self.assertIn("cid: failed at make-garment (exit 4)", self.first.stdout)

    def test_2_slurm_states_agree(self):
        # Slurm 22.05 without slurmdbd keeps no accounting for sacct: the
        # states come from the controller (scontrol), within MinJobAge.
        self.assertIn(self.summary["slurm_state_sources"], (["sacct"], ["scontrol"]))
        for name in ("ada", "bea"):
            self.assertEqual(self.rows[name]["slurm"]["state"], "COMPLETED")
            self.assertEqual(self.rows[name]["slurm"]["exit_code"], 0)
        self.assertEqual(self.rows["cid"]["slurm"]["state"], "FAILED")
        self.assertEqual(self.rows["cid"]["slurm"]["exit_code"], 4)
        # The job completion log (jobcomp/filetxt) says the same.
        logged = fit_batch.states_from_jobcomp(self.summary["array_job_id"])
        self.assertEqual({i: (s["state"], s["exit_code"]) for i, s in logged.items()},
                         {r["index"]: (r["slurm"]["state"], r["slurm"]["exit_code"]) for r in self.rows.values()})

    def test_3_summary_figures_are_the_customers_own(self):
        for name in ("ada", "bea"):
            out = os.path.join(self.customers[name], "out")
            with open(os.path.join(out, "fit", "report.json")) as f:
                fit = json.load(f)
            with open(os.path.join(out, "pattern", "report.json")) as f:
                pattern = json.load(f)
            figures = self.rows[name]["figures"]
            verified = fit["verification"]["key_poses"]
            self.assertEqual(figures["fit"]["verdict"], fit["verification"]["verdict"])
            self.assertEqual(figures["fit"]["verdict"], "pass")
            self.assertEqual(figures["fit"]["max_stretch"], max(k["max_stretch"] for k in verified))
            self.assertEqual(figures["fit"]["p99_stretch"], max(k["p99_stretch"] for k in verified))
            self.assertEqual(figures["fit"]["rest_area_growth"], fit["run"]["rest_area_growth"])
            self.assertEqual(figures["fit"]["steps"], fit["run"]["steps"])
            self.assertEqual(figures["fit"]["garment_vertices"], fit["counts"]["garment_vertices"])
            self.assertEqual(figures["pattern"]["pieces"], pattern["summary"]["pieces"])
            self.assertEqual(figures["pattern"]["total_seam_length_m"], pattern["summary"]["total_seam_length"])
            self.assertEqual(figures["pattern"]["area_2d_m2"], pattern["summary"]["area_2d"])
            self.assertEqual(figures["pattern"]["sewn_fit_verdict"], "not checked")  # NO_SEW_CHECK=1
            self.assertGreater(figures["pattern"]["pieces"], 0)
        # Two bodies, two fits.
        self.assertNotEqual(self.rows["ada"]["figures"]["fit"]["rest_area_growth"],
                            self.rows["bea"]["figures"]["fit"]["rest_area_growth"])
        with open(os.path.join(self.batch, "summary.html")) as f:
            page = f.read()
        self.assertEqual(page.count("<tr class="), 3)
        self.assertIn("<code>make-garment: error[spec]: unknown field &#x27;offsett&#x27;", page)
        self.assertIn(f'<a href="{self.rows["ada"]["report"]}">fit report</a>', page)
        self.assertIn(f'{self.rows["ada"]["figures"]["fit"]["max_stretch"]:.3f}', page)

    def test_4_resubmission_runs_no_stage_for_the_completed(self):
        reports = {n: os.path.join(self.customers[n], "out", "fit", "report.json") for n in ("ada", "bea")}
        before = {n: os.path.getmtime(p) for n, p in reports.items()}
        r, seconds = submit(self.batch, list(self.customers.values()))
        print(f"\nslurm_batch: resubmission: {seconds} s from submission to summary", file=sys.stderr)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        with open(os.path.join(self.batch, "summary.json")) as f:
            again = json.load(f)
        self.assertNotEqual(again["array_job_id"], self.summary["array_job_id"])
        rows = {row["name"]: row for row in again["rows"]}
        print("slurm_batch: tasks " + ", ".join(f"{r['name']} {r['elapsed_s']} s" for r in again["rows"]),
              file=sys.stderr)
        for name in ("ada", "bea"):
            self.assertEqual(rows[name]["state"], "completed")
            self.assertEqual(rows[name]["stages_run"], [])
            self.assertEqual(os.path.getmtime(reports[name]), before[name])
            self.assertEqual(rows[name]["figures"], self.rows[name]["figures"])
        # The failed customer's failing stage runs again, and fails again.
        self.assertEqual(rows["cid"]["stages_run"], ["make-garment"])
        self.assertEqual((rows["cid"]["failing_stage"], rows["cid"]["exit_code"]), ("make-garment", 4))


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("--bin", required=True)
    args, rest = p.parse_known_args()
    BIN = os.path.abspath(args.bin)
    try:
        local_slurm.check_can_run()
    except local_slurm.SlurmUnavailable as e:
        print(f"SKIP: cannot start a Slurm cluster here: {e}")
        sys.exit(SKIP)
    result = unittest.main(argv=[sys.argv[0]] + rest, verbosity=2, exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
