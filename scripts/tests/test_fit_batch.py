#!/usr/bin/python3
"""The Slurm batch's readers without a cluster (scripts/fit_batch.py): a
failed `make fit` named by its stage and exit code from make's own error
line, Slurm's "code:signal" exit codes, sacct's parsable output (which the
single-node test cannot produce: it has no slurmdbd), and Slurm's key=value
records of scontrol and the job completion log."""
import json
import os
import subprocess
import sys
import tempfile
import unittest
from unittest import mock

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import fit_batch  # noqa: E402


class FailingStageTest(unittest.TestCase):
    def test_the_failed_target_names_the_stage(self):
        lines = ["fit: make-avatar", "fit: register-check", "fit: make-garment",
                 "make-garment: error[spec]: unknown field 'offsett' (/c/garment-spec.json: /offsett)",
                 "make: *** [/r/pipelines/fit.mk:99: /c/out/garment/report.json] Error 4"]
        self.assertEqual(fit_batch.failing_stage("/c/out", lines, 2),
                         ("make-garment", 4, lines[3]))

    def test_make_without_line_numbers_and_a_sub_make(self):
        lines = ["fit: simulate-adapt", "make[1]: *** [/c/out/fit/report.json] Error 6"]
        self.assertEqual(fit_batch.failing_stage("/c/out", lines, 2)[:2], ("simulate-adapt", 6))

    def test_a_failed_check_names_the_stage_whose_verdict_failed(self):
        with tempfile.TemporaryDirectory() as out:
            for stage, verdict in (("fit", "pass"), ("pattern", "fail")):
                os.makedirs(os.path.join(out, stage))
                with open(os.path.join(out, stage, "report.json"), "w") as f:
                    json.dump({"verdict": verdict}, f, indent=1)
            lines = ["fit: error[check]: the garment sewn from the pattern fails its fit (see ...)",
                     "make: *** [/r/pipelines/fit.mk:150: fit] Error 8"]
            self.assertEqual(fit_batch.failing_stage(out, lines, 2), ("export-rest", 8, lines[0]))
            with open(os.path.join(out, "fit", "report.json"), "w") as f:
                json.dump({"verification": {"verdict": "fail"}}, f, indent=1)
            self.assertEqual(fit_batch.failing_stage(out, lines, 2)[:2], ("simulate-adapt", 8))

    def test_a_killed_make_names_the_last_stage_started(self):
        lines = ["fit: make-avatar", "fit: register-check", "fit: make-garment", "fit: simulate-adapt"]
        self.assertEqual(fit_batch.failing_stage("/c/out", lines, -9), ("simulate-adapt", -9, None))


class SlurmRecordsTest(unittest.TestCase):
    def test_exit_codes(self):
        self.assertEqual(fit_batch.exit_code_of("0:0"), 0)
        self.assertEqual(fit_batch.exit_code_of("4:0"), 4)
        self.assertEqual(fit_batch.exit_code_of("0:9"), 137)  # killed: 128 + the signal
        self.assertIsNone(fit_batch.exit_code_of(""))

    def test_sacct(self):
        out = "\n".join([
            "57_0|COMPLETED|0:0|00:00:35|node1",
            "57_0.batch|COMPLETED|0:0|00:00:35|node1",
            "57_1|FAILED|4:0|00:00:07|node2",
            "57_1.batch|FAILED|4:0|00:00:07|node2",
            "57_2|CANCELLED by 0|0:15|00:01:02|node1",
            "57_3|OUT_OF_MEMORY|0:125|00:00:12|node2",
            "57_[4-9]|PENDING|0:0|00:00:00|None assigned",
            "570_1|COMPLETED|0:0|00:00:01|node1",
        ]) + "\n"
        done = subprocess.CompletedProcess([], 0, out, "")
        with mock.patch.object(fit_batch, "query", return_value=done):
            states = fit_batch.states_from_sacct("57")
        self.assertEqual(sorted(states), [0, 1, 2, 3])
        self.assertEqual(states[0], {"state": "COMPLETED", "exit_code": 0, "elapsed": "00:00:35", "nodes": "node1"})
        self.assertEqual((states[1]["state"], states[1]["exit_code"]), ("FAILED", 4))
        self.assertEqual((states[2]["state"], states[2]["exit_code"]), ("CANCELLED", 128 + 15))
        self.assertEqual(states[3]["state"], "OUT_OF_MEMORY")
        refused = subprocess.CompletedProcess([], 1, "", "Slurm accounting storage is disabled\n")
        with mock.patch.object(fit_batch, "query", return_value=refused):
            self.assertIsNone(fit_batch.states_from_sacct("57"))

    def test_key_value_records(self):
        lines = [
            "JobId=60 ArrayJobId=57 ArrayTaskId=1 JobName=fit-b JobState=FAILED Reason=NonZeroExitCode "
            "ExitCode=4:0 RunTime=00:00:07 NodeList=localhost",
            "JobId=59 ArrayJobId=57 ArrayTaskId=0 JobName=fit-b JobState=COMPLETED Reason=None "
            "ExitCode=0:0 RunTime=00:00:35 NodeList=localhost",
            "JobId=61 ArrayJobId=58 ArrayTaskId=0 JobState=COMPLETED ExitCode=0:0",
            "JobId=62 JobName=fit-b-summary JobState=PENDING ExitCode=0:0",
        ]
        states = fit_batch.states_from_records(lines, "57", "JobState")
        self.assertEqual({i: (s["state"], s["exit_code"]) for i, s in states.items()},
                         {0: ("COMPLETED", 0), 1: ("FAILED", 4)})

    def test_each_task_from_the_first_source_that_knows_it(self):
        sacct = {0: {"state": "COMPLETED", "exit_code": 0, "elapsed": None, "nodes": None}}
        scontrol = {0: {"state": "FAILED", "exit_code": 1, "elapsed": None, "nodes": None},
                    1: {"state": "FAILED", "exit_code": 4, "elapsed": None, "nodes": None}}
        with mock.patch.object(fit_batch, "states_from_sacct", return_value=sacct), \
                mock.patch.object(fit_batch, "states_from_scontrol", return_value=scontrol), \
                mock.patch.object(fit_batch, "states_from_jobcomp", side_effect=AssertionError("not asked")):
            states, sources = fit_batch.slurm_states("57", {0, 1})
        self.assertEqual(sources, ["sacct", "scontrol"])
        self.assertEqual((states[0]["state"], states[1]["state"]), ("COMPLETED", "FAILED"))


class ManifestTest(unittest.TestCase):
    def test_outputs_and_refusals(self):
        with tempfile.TemporaryDirectory() as d:
            for c in ("a/x", "b/x", "y"):
                os.makedirs(os.path.join(d, c))
            m = fit_batch.make_manifest(d, "bin", [os.path.join(d, c) for c in ("a/x", "b/x", "y/")], None, [])
            self.assertEqual([e["out"] for e in m["customers"]],
                             [os.path.join(d, c, "out") for c in ("a/x", "b/x", "y")])
            m = fit_batch.make_manifest(d, "bin", [os.path.join(d, c) for c in ("a/x", "b/x", "y")], "/o", [])
            self.assertEqual([e["out"] for e in m["customers"]], ["/o/x-0", "/o/x-1", "/o/y"])
            with self.assertRaisesRegex(fit_batch.BatchError, "listed twice"):
                fit_batch.make_manifest(d, "bin", [os.path.join(d, "y"), os.path.join(d, "y/")], None, [])
            with self.assertRaisesRegex(fit_batch.BatchError, "does not exist"):
                fit_batch.make_manifest(d, "bin", [os.path.join(d, "z")], None, [])
            with self.assertRaisesRegex(fit_batch.BatchError, "no customers"):
                fit_batch.make_manifest(d, "bin", [], None, [])


if __name__ == "__main__":
    unittest.main(verbosity=2)
