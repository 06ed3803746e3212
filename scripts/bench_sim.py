"""simulate-adapt benchmarks: time per step broken down at about 1,100 and
4,000 garment vertices, the collision-culling row, and the trade-off curves
(time step, adaptation interval, solver tolerance, resolution) against the
residual error and the wall time of the run.

Every simulation runs a short motion (one transition, MOTION_FRAMES frames).
The time-per-step rows run the motion only; the culling and trade-off runs
add settling at each key pose up to a cap chosen from the measured speed so
that all planned runs fit the time left (the cap is stated in the results).
As the simulation gets faster the cap grows (up to the stage's default), and
those runs come closer to finished fits.
"""
import json
import os
import statistics

import bench_run

MOTION_FRAMES = 30
SETTLE_CAP_MAX = 1000  # simulate-adapt's own default
TARGETS = (1100, 4000)
# The time-per-step rows also run at these sizes (one run each, after the
# two-thread rows), so the step rate is plotted against the garment's size.
SWEEP = (2000, 8000)
# Trade-off points as multiples of the stage's defaults (read from its report,
# so they follow changes of the defaults), and garment sizes. Tier 1 is
# planned into the settle cap; tier 2 runs only if time is left.
TRADEOFF_TIER1 = {
    "dt": [0.25, 0.5],
    "adapt_every": [0.25, 4],
    "cg_tolerance": [1e2, 1e-2],
    "vertices": [600, 2000],
}
TRADEOFF_TIER2 = {
    "dt": [0.125, 2],
    "adapt_every": [0.5, 2],
    "cg_tolerance": [1e-4],
    "vertices": [4000],
}
OPTION = {"dt": "--dt", "adapt_every": "--adapt-every", "cg_tolerance": "--cg-tolerance"}
REPORT_OPTION = {"dt": "dt_s", "adapt_every": "adapt_every", "cg_tolerance": "cg_tolerance"}
# Relative cost of a run against the default, for planning only (the
# estimate is corrected by every finished run, and every run has a time limit).
COST = {("adapt_every", 0.25): 1.6, ("adapt_every", 0.5): 1.2, ("dt", 0.125): 1.1, ("cg_tolerance", 1e-2): 1.1, ("cg_tolerance", 1e-4): 1.2}
NO_CULL_REACH = 10.0  # [m]: keeps every body face
NO_CULL_COST = 2.0  # planning: a run without culling took about twice as long here
# Settling steps of the calibration run that measures what a settling step
# costs against a motion step (it varies with the solver: 3x to 0.5x here).
CALIBRATION_CAP = 20
# Time per step grows faster than the vertex count (measured here: 0.36 s per
# step per 1,000 vertices at 1,100 and 0.49-0.56 at 4,000 on a loaded
# machine); planning scales by (vertices / 1,000) ** SIZE_EXPONENT.
SIZE_EXPONENT = 1.25


class Scene:
    """A garment on a body: spec, optional extension, seams, a short motion."""

    def __init__(self, name, body, poses_json, spec, extend, seams, motion_poses):
        self.name = name
        self.body = body
        self.poses_json = poses_json
        self.spec = spec
        self.extend = extend
        self.seams = seams
        self.motion_poses = motion_poses
        self.garments = {}

    def label(self):
        return f"{self.name} ({self.body} body)"

    def motion_file(self, run):
        path = run.path(f"motion-{self.name.replace(' ', '-')}.json")
        with open(path, "w") as f:
            json.dump({"schema": "motion/1", "steps": MOTION_FRAMES, "sequence": self.motion_poses}, f)
        return path

    def motion_text(self):
        return f"{' -> '.join(self.motion_poses)}, {MOTION_FRAMES} frames"

    def garment(self, run, target):
        """(garment.json, vertex count) with about `target` vertices in the
        simulated garment (after the extension, which adds a skirt of about
        the garment's own size, so the design count is corrected once)."""
        if target in self.garments:
            return self.garments[target]
        with open(self.spec) as f:
            spec = json.load(f)
        design = target if not self.extend else max(200, target // 2)
        for _ in range(2):
            path, count = self._make(run, spec, design, target)
            if abs(count / target - 1.0) < 0.1:
                break
            design = max(200, round(design * target / count))
        self.garments[target] = (path, count)
        return path, count

    def _make(self, run, spec, design, target):
        tag = f"{self.name.replace(' ', '-')}-{target}"
        spec = dict(spec, resolution={"vertex_count": design})
        spec_path = run.path(f"spec-{tag}.json")
        with open(spec_path, "w") as f:
            json.dump(spec, f)
        out = run.prepare([run.tool("make-garment"), spec_path, "--poses", self.poses_json],
                          run.path(f"garment-{tag}"), f"the {self.name} at {target} vertices")
        path = os.path.join(out, "garment.json")
        if self.extend:
            out = run.prepare([run.tool("extend-boundary"), path, self.extend], run.path(f"extended-{tag}"),
                              f"the {self.name}'s extension")
            path = os.path.join(out, "garment.json")
        with open(path) as f:
            return path, json.load(f)["mesh"]["vertex_count"]


def read_timing(out_dir):
    with open(os.path.join(out_dir, "timing.json")) as f:
        return json.load(f)


def median_timing(per_run):
    """Per-phase medians over the runs' timing.json (the runs' step counts are
    identical: same inputs give the same simulation)."""
    phases = sorted({k for t in per_run for k in t["ms_per_step"]})
    return {
        "steps_per_s": statistics.median(t["steps_per_s"] for t in per_run),
        "run_s": statistics.median(t["run_s"] for t in per_run),
        "ms_per_step": {k: statistics.median(t["ms_per_step"].get(k, 0.0) for t in per_run) for k in phases},
    }


def sim_summary(m):
    """Figures of a simulate-adapt measurement: the report of its output
    folder, the medians of the runs' timings."""
    r = m.json("report.json")
    t = median_timing(m.per_run) if m.per_run else m.json("timing.json")
    keys = r["key_poses"]
    return {
        "runs": m.runs, "median_s": m.median, "min_s": m.lo, "max_s": m.hi, "peak_mib": m.peak_mib,
        "vertices": r["counts"]["garment_vertices"],
        "body_faces": r["counts"]["body_faces"], "body_faces_kept": r["counts"]["body_faces_kept"],
        "steps": r["run"]["steps"], "settle_steps": sum(k["settle_steps"] for k in keys),
        "rejected_steps": r["run"]["rejected_steps"],
        "cg_iterations": m.json("timing.json")["work"]["cg_iterations"], "adaptations": r["run"]["adaptations"],
        "all_settled": r["run"]["all_settled"], "arap_converged": r["run"]["arap_converged"],
        "solver": r["options"]["solver"],
        "steps_per_s": t["steps_per_s"], "ms_per_step": t["ms_per_step"], "run_s": t["run_s"],
        "max_stretch": max(k["max_stretch"] for k in keys),
        "p99_stretch": max(k["p99_stretch"] for k in keys),
        "area_above_limit": max(k["area_fraction_above_limit"] for k in keys),
        "penetration_m": max(k["deepest_penetration_m"] for k in keys),
        "rest_area_growth": r["run"]["rest_area_growth"],
    }


class SimBench:
    """Plans and runs the simulate-adapt benchmarks for the given scenes
    (the first scene carries the culling row and the trade-off curves).

    Time per step: every scene at every target size through the motion only
    (settle cap 0: MOTION_FRAMES steps with adaptation, no settling), cheap
    enough to repeat. Culling and trade-offs: the same motion plus settling
    at each key pose up to a cap planned from the measured speed."""

    def __init__(self, run, scenes, quick, results, notes):
        self.run = run
        self.scenes = scenes
        self.quick = quick
        self.results = results
        self.notes = notes
        self.step_cost = None  # wall seconds per step per 1,000 vertices at default settings
        self.overhead = 0.0
        self.defaults = {}  # the stage's defaults of the varied options, from its report
        self.settle_cost = 1.0  # cost of a settling step in motion steps, measured by calibrate()
        self.cap = 0
        self.measured = {}
        self.failed = {}
        self.skipped = []

    def args(self, scene, garment, cap, extra, threads=1):
        # One adaptation run, timed per step: --no-verify, since the verification
        # (a second run without adaptation, and further cycles while it fails)
        # would mix other work into the step rates and exit 8 on a capped run.
        return [self.run.tool("simulate-adapt"), "--poses", scene.poses_json, "--motion", scene.motion_file(self.run),
                "--garment", garment, "--settle-max-steps", str(cap), "--workers", str(threads), "--no-verify",
                *extra]

    def predict(self, vertices, factor, cap):
        steps = MOTION_FRAMES + self.settle_cost * 2 * cap
        return self.overhead + steps * self.step_cost * (vertices / 1000.0) ** SIZE_EXPONENT * factor

    def learn(self, m, factor):
        s = sim_summary(m)
        weighted = s["steps"] - s["settle_steps"] + self.settle_cost * s["settle_steps"]
        per_step = s["run_s"] / max(1.0, weighted) / (s["vertices"] / 1000.0) ** SIZE_EXPONENT / factor
        self.overhead = max(0.0, m.median - s["run_s"])
        # The latest runs describe the machine's current load best; settling
        # steps cost more than motion steps, so the estimate only grows by
        # the latest figure and shrinks by half the difference.
        self.step_cost = per_step if self.step_cost is None else max(per_step, 0.5 * (self.step_cost + per_step))
        return s

    def targets(self):
        return TARGETS[:1] if self.quick else TARGETS

    def sweep(self):
        """Every size of the time-per-step rows, ascending."""
        return self.targets() if self.quick else tuple(sorted(TARGETS + SWEEP))

    def tier(self, tier):
        if tier is TRADEOFF_TIER2:
            return {} if self.quick else tier
        return {k: v[:1] for k, v in tier.items()} if self.quick else tier

    def value(self, key, multiple):
        v = self.defaults[key] * multiple
        return max(1, round(v)) if key == "adapt_every" else float(f"{v:.6g}")

    def tradeoff_jobs(self, tier):
        """(run key, target vertices, extra options, cost factor, parameter, value) of a tier."""
        jobs = []
        for key, values in self.tier(tier).items():
            for x in values:
                if key == "vertices":
                    jobs.append((f"sim-res-{x}", x, [], 1.0, key, x))
                else:
                    v = self.value(key, x)
                    jobs.append((f"sim-{key}-{v}", TARGETS[0], [OPTION[key], str(v)], COST.get((key, x), 1.0), key, v))
        return jobs

    def calibrate(self, reserve_s):
        """Cost of a settling step against a motion step, from the base scene
        at ~1,100 vertices run with CALIBRATION_CAP settling steps beside its
        motion-only row."""
        base = self.scenes[0]
        motion = self.measured.get(self.breakdown_key(base, TARGETS[0]))
        if motion is None:
            return
        garment, _count = base.garment(self.run, TARGETS[0])
        try:
            m = self.run.measure("sim-calibration", self.args(base, garment, CALIBRATION_CAP, []), repeats=1,
                                 timeout_s=max(60.0, 10.0 * motion["median_s"]), collect=read_timing)
        except bench_run.StageFailed as e:
            self.run.say(f"sim-calibration: failed ({e.short}); settling steps costed as motion steps")
            return
        s = sim_summary(m)
        motion_step = motion["run_s"] / max(1, motion["steps"])
        extra_steps = s["steps"] - motion["steps"]
        if extra_steps > 0:
            ratio = (s["run_s"] - motion["run_s"]) / extra_steps / motion_step
            self.settle_cost = min(5.0, max(0.3, ratio))
        self.run.say(f"sim-calibration: a settling step costs {self.settle_cost:.2f} motion steps")

    def plan(self, budget_s):
        """Largest settle cap at which the culling and tier-1 trade-off runs fit budget_s."""
        base = self.scenes[0]
        # default settings; culling off; the same two with a fixed rest shape
        jobs = [(TARGETS[0], 1.0), (TARGETS[0], NO_CULL_COST), (TARGETS[0], 0.8), (TARGETS[0], NO_CULL_COST)]
        jobs += [(job[1], job[3]) for job in self.tradeoff_jobs(TRADEOFF_TIER1)]
        jobs = [(base.garment(self.run, t)[1], f) for t, f in jobs]
        fixed = sum(self.predict(v, f, 0) for v, f in jobs)
        per_cap_step = sum(self.settle_cost * 2 * self.step_cost * (v / 1000.0) ** SIZE_EXPONENT * f for v, f in jobs)
        cap = int((budget_s - fixed) / per_cap_step) if per_cap_step > 0 else SETTLE_CAP_MAX
        self.cap = max(0, min(SETTLE_CAP_MAX, cap // 10 * 10))
        self.run.say(f"simulate-adapt plan: {len(jobs)} runs in {budget_s:.0f} s -> settle cap {self.cap} steps "
                     f"(estimate {self.step_cost:.3f} s per step per 1,000 vertices)")

    def sim(self, key, scene, target, extra, cap, factor=1.0, reserve_s=0.0, repeats=1, threads=1):
        """One measured configuration, skipped when its predicted time does not
        fit before the deadline (keeping reserve_s)."""
        garment, count = scene.garment(self.run, target)
        if self.step_cost is not None:
            predicted = self.predict(count, factor, cap)
            if predicted > self.run.remaining() - reserve_s:
                self.skipped.append(f"{key} (predicted {predicted:.0f} s, {self.run.remaining():.0f} s left)")
                self.run.say(f"{key}: skipped, predicted {predicted:.0f} s")
                return None
            self.run.say(f"{key}: {count} vertices, predicted {predicted:.0f} s per run")
            timeout = max(60.0, 3.0 * predicted)
        else:
            timeout = None
        m = None
        for attempt in range(2):
            try:
                m = self.run.measure(key, self.args(scene, garment, cap, extra, threads), repeats=repeats,
                                     timeout_s=timeout, keep_first=True, collect=read_timing)
                break
            except bench_run.StageFailed as e:
                self.run.say(f"{key}: failed: {e}")
                # A signal the benchmark did not send comes from outside (the
                # machine is shared): one more try.
                if not e.signal or attempt == 1:
                    self.failed[key] = e.short
                    return None
        s = sim_summary(m) if threads > 1 else self.learn(m, factor)
        s.update(scene=scene.label(), motion=scene.motion_text(), cap=cap, measurement=m, args=extra,
                 factor=factor, threads=threads)
        if m.runs > 1:
            s["repeat_diff"] = compare_outputs(m.out_dir + "-run1", m.out_dir)
        self.measured[key] = s
        return s

    def repeat(self, key, reserve_s):
        """One more run of a measured configuration if it fits."""
        s = self.measured[key]
        m = s["measurement"]
        if m.median > self.run.remaining() - reserve_s:
            return False
        scene = next(sc for sc in self.scenes if sc.label() == s["scene"])
        garment = next(g for g, n in scene.garments.values() if n == s["vertices"])
        again = f"{m.out_dir}-run{m.runs + 1}"
        try:
            wall, peak = self.run.run_once(self.args(scene, garment, s["cap"], s["args"], s["threads"]), again)
        except bench_run.StageFailed as e:
            self.run.say(f"{key}: repeat failed: {e}")
            return False
        m.times.append(wall)
        m.peaks_mib.append(peak)
        m.per_run.append(read_timing(again))
        t = median_timing(m.per_run)
        s.update(runs=m.runs, median_s=m.median, min_s=m.lo, max_s=m.hi, peak_mib=m.peak_mib,
                 steps_per_s=t["steps_per_s"], ms_per_step=t["ms_per_step"], run_s=t["run_s"])
        if "repeat_diff" not in s:
            s["repeat_diff"] = compare_outputs(m.out_dir, again)
        self.run.say(f"{key}: run {m.runs}, {wall:.1f} s")
        return True

    def breakdown_key(self, scene, target):
        return f"step-{scene.name.replace(' ', '-')}-{target}"

    def execute(self, reserve_s):
        """Runs the plan; reserve_s is kept for writing the results."""
        for scene in self.scenes:
            for target in self.targets():
                self.sim(self.breakdown_key(scene, target), scene, target, [], 0, reserve_s=reserve_s,
                         repeats=self.run.repeats if target == TARGETS[0] else 1)
        # The same rows with simulate-adapt's default of two threads (the body
        # frames and the adaptations beside the stepping): not used for
        # planning, whose estimates are one core's.
        for scene in self.scenes:
            for target in self.targets():
                if self.breakdown_key(scene, target) in self.measured:
                    self.sim(self.breakdown_key(scene, target) + "-threads-2", scene, target, [], 0,
                             reserve_s=reserve_s, repeats=self.run.repeats if target == TARGETS[0] else 1, threads=2)
        for scene in self.scenes:
            for target in self.sweep():
                if target not in TARGETS:
                    self.sim(self.breakdown_key(scene, target), scene, target, [], 0, reserve_s=reserve_s)
        first = self.measured.get(self.breakdown_key(self.scenes[0], TARGETS[0]))
        if first is None:
            return self.collect()
        options = first["measurement"].json("report.json")["options"]
        self.defaults = {k: options[REPORT_OPTION[k]] for k in OPTION}
        self.calibrate(reserve_s)
        self.plan(0.85 * (self.run.remaining() - reserve_s))
        base = self.scenes[0]
        same = self.measured.get(self.breakdown_key(base, TARGETS[0]))
        if self.cap == 0 and same:
            self.measured["sim-default"] = same  # the same command as the time-per-step row
        else:
            self.sim("sim-default", base, TARGETS[0], [], self.cap, reserve_s=reserve_s)
        self.sim("sim-noculling", base, TARGETS[0], ["--reach", repr(NO_CULL_REACH)], self.cap, NO_CULL_COST,
                 reserve_s)
        # The same pair with a fixed rest shape: tells what the culling changes
        # in the simulation alone from what adaptation makes of it.
        self.sim("sim-noadapt-culling", base, TARGETS[0], ["--no-adapt"], self.cap, 0.8, reserve_s)
        self.sim("sim-noadapt-noculling", base, TARGETS[0], ["--no-adapt", "--reach", repr(NO_CULL_REACH)], self.cap,
                 NO_CULL_COST, reserve_s)
        for tier in (TRADEOFF_TIER1, TRADEOFF_TIER2):
            for key, target, extra, factor, _param, _value in self.tradeoff_jobs(tier):
                self.sim(key, base, target, extra, self.cap, factor, reserve_s)
        # A reach between the default and the whole body tells a culling miss
        # (it would differ from the whole body) from rounding amplified by the
        # motion (it differs from both).
        if not self.quick:
            self.sim("sim-reach-0.3", base, TARGETS[0], ["--reach", "0.3"], self.cap, 1.1, reserve_s)
        # More runs for the medians while time is left.
        primary = [self.breakdown_key(sc, t) + suffix for suffix in ("", "-threads-2") for sc in self.scenes
                   for t in self.targets()]
        primary = [k for k in primary + ["sim-default", "sim-noculling"] if k in self.measured]
        primary = [k for i, k in enumerate(primary) if all(self.measured[k] is not self.measured[p] for p in primary[:i])]
        for _round in range(2):
            for key in primary:
                self.repeat(key, reserve_s)
        self.collect()

    def collect(self):
        self.results["sim_breakdown"] = [self.measured[self.breakdown_key(sc, t)] for sc in self.scenes
                                         for t in self.sweep() if self.breakdown_key(sc, t) in self.measured]
        self.results["sim_breakdown_failed"] = {k: v for k, v in self.failed.items() if k.startswith("step-")}
        threads = []
        for sc in self.scenes:
            for t in self.targets():
                one, two = (self.measured.get(self.breakdown_key(sc, t) + suffix) for suffix in ("", "-threads-2"))
                if one and two:
                    threads.append({"one": one, "two": two, "diff": compare_outputs(one["measurement"].out_dir,
                                                                                   two["measurement"].out_dir)})
        self.results["sim_threads"] = threads
        self.results["sim_cap"] = self.cap
        self.results["sim_frames"] = MOTION_FRAMES
        self.results["sim_skipped"] = self.skipped
        shown = {k for k in self.failed if k.startswith(("step-", "sim-res-", "sim-dt-", "sim-adapt_every-",
                                                            "sim-cg_tolerance-"))}
        for key, why in self.failed.items():
            if key not in shown:
                self.notes.append(f"simulate-adapt run {key} failed: {why}")
        base = self.measured.get("sim-default")
        off = self.measured.get("sim-noculling")
        if base and off:
            culling = {"with": base, "without": off, "repeat": base.get("repeat_diff"),
                       "diff": compare_outputs(base["measurement"].out_dir, off["measurement"].out_dir)}
            mid = self.measured.get("sim-reach-0.3")
            if mid:
                culling["mid"] = mid
                culling["mid_diff"] = compare_outputs(mid["measurement"].out_dir, off["measurement"].out_dir)
            fixed_on, fixed_off = self.measured.get("sim-noadapt-culling"), self.measured.get("sim-noadapt-noculling")
            if fixed_on and fixed_off:
                culling["fixed"] = (fixed_on, fixed_off, compare_outputs(fixed_on["measurement"].out_dir,
                                                                         fixed_off["measurement"].out_dir))
            self.results["culling"] = culling
        curves = {}
        if base:
            jobs = self.tradeoff_jobs(TRADEOFF_TIER1) + self.tradeoff_jobs(TRADEOFF_TIER2)
            for key in ("dt", "adapt_every", "cg_tolerance", "vertices"):
                points = []
                for name, _target, _extra, _factor, param, v in jobs:
                    if param != key:
                        continue
                    s = self.measured.get(name)
                    if s:
                        points.append((s["vertices"] if key == "vertices" else v, s))
                    elif name in self.failed:
                        points.append((v, {"failed": self.failed[name]}))
                points.append((base["vertices"] if key == "vertices" else self.defaults[key], base))
                curves[key] = sorted(points, key=lambda p: p[0])
            self.results["tradeoff_defaults"] = dict(self.defaults)
        self.results["tradeoff"] = curves


def compare_outputs(a_dir, b_dir):
    """Largest vertex distance [m] and byte identity between the meshes of two
    simulate-adapt output folders (rest shape and every draped key pose)."""
    import hashlib
    import meshdiff

    files = sorted(f for f in os.listdir(a_dir) if f.endswith(".ply"))
    worst, identical, per_file = 0.0, True, []
    for name in files:
        a, b = os.path.join(a_dir, name), os.path.join(b_dir, name)
        if not os.path.exists(b):
            per_file.append((name, float("nan"), False))
            identical = False
            continue
        with open(a, "rb") as fa, open(b, "rb") as fb:
            same = hashlib.sha256(fa.read()).digest() == hashlib.sha256(fb.read()).digest()
        r = meshdiff.compare(a, b, 0.0, 0.0, False)
        d = r["max"] if r["topology"] == "same" else r["hausdorff"]
        worst = max(worst, d)
        identical = identical and same
        per_file.append((name, d, same))
    return {"files": per_file, "max_m": worst, "byte_identical": identical}
