"""Running the pipeline's stages for the benchmarks: one process per run,
wall time and the peak resident memory of exactly that process, repeats
within a time budget, and progress lines on stdout.

Used by scripts/bench.py; see there for what is measured.
"""
import json
import os
import shutil
import statistics
import subprocess
import threading
import time


class StageFailed(RuntimeError):
    """A stage exited with a non-zero code or was stopped at its time limit;
    `short` is the exit code and the stage's last error line."""

    def __init__(self, message, short=None, signal=False):
        super().__init__(message)
        self.short = short or message
        self.signal = signal  # ended by a signal the benchmark did not send


class Measurement:
    """Repeated runs of one command: wall times [s], peak memory [MiB] and
    the output folder of the last run."""

    def __init__(self, name, out_dir):
        self.name = name
        self.out_dir = out_dir
        self.times = []
        self.peaks_mib = []
        self.per_run = []  # what the `collect` function of measure() returned for each run

    @property
    def runs(self):
        return len(self.times)

    @property
    def median(self):
        return statistics.median(self.times)

    @property
    def lo(self):
        return min(self.times)

    @property
    def hi(self):
        return max(self.times)

    @property
    def peak_mib(self):
        return max(self.peaks_mib)

    def json(self, name):
        with open(os.path.join(self.out_dir, name)) as f:
            return json.load(f)


class Runner:
    """Runs stages from bin_dir with outputs under work, against a deadline of
    budget_s seconds from construction."""

    def __init__(self, bin_dir, work, budget_s, repeats):
        self.bin = bin_dir
        self.work = work
        self.repeats = repeats
        self.t0 = time.perf_counter()
        self.budget_s = budget_s
        self.processes = 0
        self.last_cpu = 0.0  # user + system CPU of the last run_once's process [s]

    def tool(self, name):
        path = os.path.join(self.bin, name)
        if not os.access(path, os.X_OK):
            raise StageFailed(f"{path} not found (build it first: make bench builds the stages)")
        return path

    def elapsed(self):
        return time.perf_counter() - self.t0

    def remaining(self):
        return self.budget_s - self.elapsed()

    def say(self, text):
        print(f"bench [{self.elapsed():5.0f} s] {text}", flush=True)

    def path(self, *parts):
        return os.path.join(self.work, *parts)

    def run_once(self, args, out_dir, timeout_s=None):
        """One run with --out out_dir; returns (wall [s], peak resident memory [MiB]).

        The peak memory is the child's own ru_maxrss from wait4, not the
        cumulative maximum over all children of this script."""
        if os.path.exists(out_dir):
            shutil.rmtree(out_dir)
        log_path = out_dir + ".log"
        with open(log_path, "w") as log:
            t0 = time.perf_counter()
            proc = subprocess.Popen(args + ["--out", out_dir, "--quiet"], stdout=log, stderr=log)
            timer = None
            stopped = []
            if timeout_s is not None:
                def stop():
                    stopped.append(True)
                    proc.kill()
                timer = threading.Timer(timeout_s, stop)
                timer.start()
            _, status, usage = os.wait4(proc.pid, 0)
            wall = time.perf_counter() - t0
            self.last_cpu = usage.ru_utime + usage.ru_stime
            if timer is not None:
                timer.cancel()
            proc.returncode = os.waitstatus_to_exitcode(status)
        self.processes += 1
        if stopped:
            raise StageFailed(f"{os.path.basename(args[0])} stopped at its time limit of {timeout_s:.0f} s",
                              f"stopped at the benchmark's time limit of {timeout_s:.0f} s")
        if proc.returncode != 0:
            with open(log_path) as f:
                err = f.read().strip().splitlines()
            last = err[-1] if err else ""
            raise StageFailed(f"{' '.join(args)} exited {proc.returncode}: {last}", f"exit {proc.returncode}: {last}",
                              signal=proc.returncode < 0)
        return wall, usage.ru_maxrss / 1024.0

    def measure(self, name, args, repeats=None, budget_s=None, timeout_s=None, keep_first=False, collect=None):
        """Runs args up to `repeats` times (default: the runner's count), fewer
        when the next run would end after budget_s seconds from now or after the
        runner's deadline; at least once. Returns a Measurement. keep_first:
        the first run's output folder is kept as <out>-run1 (for comparing runs);
        collect(out_dir), if given, is stored in Measurement.per_run after each run."""
        repeats = repeats or self.repeats
        m = Measurement(name, self.path(name))
        start = self.elapsed()
        while m.runs < repeats:
            if m.runs > 0:
                predicted = self.elapsed() + m.median
                if predicted > self.budget_s or (budget_s is not None and predicted - start > budget_s):
                    break
                if keep_first and m.runs == 1:
                    os.rename(m.out_dir, m.out_dir + "-run1")
            wall, peak = self.run_once(args, m.out_dir, timeout_s)
            m.times.append(wall)
            m.peaks_mib.append(peak)
            if collect is not None:
                m.per_run.append(collect(m.out_dir))
        self.say(f"{name}: {m.runs} run(s), median {m.median:.2f} s, peak {m.peak_mib:.0f} MiB")
        return m

    def prepare(self, args, out_dir, what):
        """A preparation step (not measured): runs once, fails loudly."""
        r = subprocess.run(args + ["--out", out_dir, "--force", "--quiet"], capture_output=True, text=True)
        self.processes += 1
        if r.returncode != 0:
            raise StageFailed(f"preparing {what}: {' '.join(args)} exited {r.returncode}: {r.stderr.strip()}")
        return out_dir


