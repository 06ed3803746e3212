#!/usr/bin/python3
"""Benchmarks of the pipeline's stages, written to BENCHMARKS.md with PNG
plots in a regenerated folder.

Each benchmark runs a stage as a user would (a separate process), repeated
where the time allows, and reports the median wall time, the spread, the
peak resident memory of the process and figures the stage writes into its
timing.json / report.json. Machine, thread count, load and date are stated.

Inputs: the shared registered body (../shared/avatars) with the example
shirt and dress of pipelines/customers/slim-shirt and slim-dress, and the
demo customer's generated body; without ../shared the simulation benchmarks
fall back to the demo shirt on the generated body.

The whole run keeps to --budget seconds: the cheap stages run first with
their repeats, then simulate-adapt gets the time left (see bench_sim.py).
Progress lines go to stdout.
"""
import argparse
import datetime
import json
import os
import platform
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_plots  # noqa: E402
import bench_report  # noqa: E402
import bench_run  # noqa: E402
import bench_sim  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SHARED = os.path.abspath(os.path.join(ROOT, "..", "shared", "avatars"))
CUSTOMERS = os.path.join(ROOT, "pipelines", "customers")
# Seconds kept at the end for the comparison of meshes, plots and the file.
RESERVE_S = 30.0


def machine():
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def load_average():
    try:
        return "/".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


class Bench:
    def __init__(self, run, quick):
        self.run = run
        self.quick = quick
        self.rows = []      # (stage, case, threads, Measurement, detail)
        self.notes = []
        self.results = {"interp": [], "export": []}

    def row(self, stage, case, threads, m, detail):
        self.rows.append((stage, case, threads, m, detail))

    # --- cheap stages ---------------------------------------------------------

    def register_check(self):
        if not os.path.isdir(SHARED):
            self.notes.append("register-check on the shared avatars: skipped (../shared/avatars not found)")
            return
        poses = [os.path.join(SHARED, f"slim_{p}.ply") for p in ("apose", "tpose", "armsup", "armsbent")]
        for threads in (1, 2):
            m = self.run.measure(f"rc{threads}", [self.run.tool("register-check"), *poses, "--threads", str(threads)])
            t = m.json("timing.json")
            self.row("register-check", "shared body, 4 poses x 27,578 vertices, self-intersections on", threads, m,
                     f"read {t['read_s']:.3f} s, checks {t['checks_s']:.3f} s, "
                     f"self-intersections {t['self_intersections_s']:.3f} s (target < 2 s)")

    def make_avatar(self):
        poses = "apose,tpose,armsup,armsforward,elbowsbent,stepforward"
        for res in ("default", "small"):
            m = self.run.measure(f"avatar-{res}", [self.run.tool("make-avatar"), "--poses", poses, "--resolution", res])
            r = m.json("report.json")
            t = m.json("timing.json")
            phases = ", ".join(f"{k} {v:.2f} s" for k, v in t.items() if isinstance(v, float) and k != "total")
            self.row("make-avatar", f"default body, 6 poses, {r['mesh']['vertex_count']} vertices ({res})", 1, m,
                     f"largest girth error {1000 * r['max_girth_error_m']:.2f} mm, largest volume change between "
                     f"poses {100 * r['max_pairwise_volume_change']:.2f} % (target < 2 s at default); {phases}")

    def interp_poses(self):
        if not os.path.isdir(SHARED):
            self.notes.append("interp-poses on the shared avatars: skipped (../shared/avatars not found)")
            return
        poses = [os.path.join(SHARED, f"slim_{p}.ply") for p in ("apose", "armsup")]
        motion = os.path.join(ROOT, "testdata", "motions", "apose_armsup.json")
        for method in ("nonlinear", "linear"):
            m = self.run.measure(f"interp-{method}", [self.run.tool("interp-poses"), *poses, "--motion", motion,
                                                      "--method", method, "--keys-only", "--threads", "1"])
            t = m.json("timing.json")
            summary = m.json("report.json")["summary"]
            detail = (f"factorization {t['factorization_ms']:.1f} ms, {t['ms_per_frame_mean']:.2f} ms/frame wall "
                      f"({t['cpu_ms_per_frame_mean']:.2f} ms CPU; target < 15 ms), 61 frames; edge-length "
                      f"excursion beyond the keys' range max {100 * summary['edge_excess_max']:.1f} %, volume "
                      f"{100 * summary['volume_excess_max']:.2f} %")
            if "linear_vs_nonlinear" in summary:
                d = summary["linear_vs_nonlinear"]
                detail += (f"; linear baseline against it: edge deviation max {100 * d['edge_deviation_max']:.0f} % "
                           f"/ mean {100 * d['edge_deviation_mean']:.1f} %, volume {100 * d['volume_error']:.1f} %, "
                           f"vertex distance {d['vertex_distance_max_m']:.3f} m")
            self.row("interp-poses", f"shared body A-pose -> arms up, 60 steps, {method}", 1, m, detail)
            self.results["interp"].append({
                "method": method, "ms_per_frame": t["ms_per_frame_mean"], "runs": m.runs,
                "edge_excess": summary["edge_excess_max"], "volume_excess": summary["volume_excess_max"]})

    def register_for(self, reference):
        return self.run.prepare([self.run.tool("register-check"), SHARED, "--reference", reference,
                                 "--no-self-intersections"], self.run.path(f"poses-{reference}"),
                                f"the shared poses (reference {reference})")

    def make_garment(self):
        """Design rows for the shared shirt and dress at their spec resolution;
        returns {name: garment.json} of the designed garments."""
        designed = {}
        if not os.path.isdir(SHARED):
            self.notes.append("make-garment on the shared avatars: skipped (../shared/avatars not found)")
            return designed
        for name, reference in (("shirt", "slim_tpose"), ("dress", "slim_apose")):
            customer = os.path.join(CUSTOMERS, f"slim-{name}")
            poses = os.path.join(self.register_for(reference), "poses.json")
            m = self.run.measure(f"garment-{name}", [self.run.tool("make-garment"),
                                                     os.path.join(customer, "garment-spec.json"), "--poses", poses])
            q = m.json("report.json")["quality"]
            t = m.json("timing.json")
            phases = ", ".join(f"{k[:-2]} {v:.2f} s" for k, v in t.items() if k.endswith("_s") and k != "total_s")
            g = m.json("garment.json")
            self.row("make-garment", f"{name} on the shared body, {g['mesh']['vertex_count']} garment vertices", 1, m,
                     f"{phases}; min angle > 20 deg for {100 * q['fraction_min_angle_over_20_deg']:.1f} % of "
                     f"triangles, edges within 30 % for {100 * q['fraction_edges_within_30_percent']:.1f} %, "
                     f"offset error max {1000 * q['offset_max_error']:.2f} mm (target < 3 s)")
            designed[name] = os.path.join(m.out_dir, "garment.json")
            extend = os.path.join(customer, "extend.json")
            if os.path.exists(extend):
                e = self.run.measure(f"extend-{name}", [self.run.tool("extend-boundary"), designed[name], extend])
                ext = e.json("report.json")["extension"]
                g = e.json("garment.json")
                self.row("extend-boundary", f"{name} waist -> skirt hem on the shared body, "
                         f"{g['mesh']['vertex_count']} garment vertices after", 1, e, f"hem girth {ext['new_girth']:.3f} m")
                designed[name] = os.path.join(e.out_dir, "garment.json")
        return designed

    def demo_fit(self):
        """The demo customer's body and garment through pipelines/fit.mk (not
        measured here: make-avatar has its own rows)."""
        import subprocess

        out = self.run.path("demo-fit")
        demo = os.path.join(CUSTOMERS, "demo")
        r = subprocess.run(["make", "--no-print-directory", "-s", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
                            f"CUSTOMER={demo}", f"OUT={out}", f"BIN={self.run.bin}", f"{out}/garment/report.json"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise bench_run.StageFailed(f"preparing the demo fit: {r.stderr.strip()}")
        self.run.say("demo customer's body and garment ready")
        return out

    def export_rest(self, designed, demo):
        """Distortion limit against pieces, seam length and time, on the
        designed garments (make-garment output) as rest shapes, so that the
        rows do not depend on how far the simulation ran."""
        cases = [("demo shirt", os.path.join(demo, "garment", "garment.json"),
                  os.path.join(CUSTOMERS, "demo", "seams.json"), os.path.join(demo, "poses", "poses.json"),
                  self.run.repeats)]
        for name in ("shirt", "dress"):
            if name in designed:
                seams = os.path.join(CUSTOMERS, f"slim-{name}", "seams.json")
                body = self.run.path(f"poses-{'slim_tpose' if name == 'shirt' else 'slim_apose'}", "poses.json")
                cases.append((f"shared-body {name}", designed[name], seams, body, 1))
        limits = [("looser", 0.05, 0.10), ("default", 0.02, 0.05), ("tighter", 0.01, 0.03)]
        if self.quick:
            limits = limits[1:2]
        for case, garment, seams, body, repeats in cases:
            with open(garment) as f:
                vertices = json.load(f)["mesh"]["vertex_count"]
            rest = os.path.join(os.path.dirname(garment), "garment.ply")
            for label, p95, mx in limits:
                key = f"export-{case.replace(' ', '-')}-{label}"
                try:
                    m = self.run.measure(key, [self.run.tool("export-rest"), rest, "--garment", garment, "--seams", seams,
                                               "--body", body, "--p95-limit", repr(p95), "--max-limit", repr(mx)],
                                         repeats=repeats)
                except bench_run.StageFailed as e:
                    self.notes.append(f"export-rest, {case}, {label} limit: failed: {e}")
                    continue
                sm = m.json("report.json")["summary"]
                self.row("export-rest", f"{case} as designed ({vertices} vertices), {label} limit "
                         f"{100 * p95:.0f} % / {100 * mx:.0f} %", 1, m,
                         f"{sm['pieces']} pieces, {sm['added_cuts']} added cuts, seam length "
                         f"{sm['total_seam_length']:.2f} m, worst p95 {100 * sm['worst_p95_error']:.2f} %, max "
                         f"{100 * sm['worst_max_error']:.2f} %, limit met: {'yes' if sm['meets_distortion_limit'] else 'no'}")
                self.results["export"].append({
                    "garment": case, "vertices": vertices, "label": label, "p95_limit": p95, "max_limit": mx,
                    "pieces": sm["pieces"], "seam_length": sm["total_seam_length"], "median_s": m.median,
                    "runs": m.runs, "met": sm["meets_distortion_limit"]})

    # --- simulation -----------------------------------------------------------

    def whole_fit(self, demo):
        """The demo's whole simulate-adapt (fit and verification, its
        customer's flags, one worker) with the damped settling and with the
        static solve, in interleaved pairs (the order swapped every pair), so
        that the ratio of their CPU times is taken under the same load: issue
        45's speed figure."""
        pairs = 1 if self.quick else 3
        # The customer's SIMULATE_FLAGS as pipelines/fit.mk recorded them for demo_fit.
        with open(os.path.join(demo, "flags", "simulate-adapt")) as f:
            flags = f.read().split()
        args = [self.run.tool("simulate-adapt"), "--poses", os.path.join(demo, "poses", "poses.json"),
                "--motion", os.path.join(CUSTOMERS, "demo", "motion.json"),
                "--garment", os.path.join(demo, "garment", "garment.json"), "--workers", "1", *flags]
        runs = {"dynamic": [], "static": []}
        for pair in range(pairs):
            order = ("dynamic", "static") if pair % 2 == 0 else ("static", "dynamic")
            for solver in order:
                out = self.run.path(f"whole-fit-{solver}")
                try:
                    wall, _ = self.run.run_once(args + ["--solver", solver], out)
                except bench_run.StageFailed as e:
                    self.notes.append(f"whole fit, {solver}: failed: {e}")
                    return
                with open(os.path.join(out, "report.json")) as f:
                    r = json.load(f)
                with open(os.path.join(out, "timing.json")) as f:
                    t = json.load(f)
                runs[solver].append({
                    "cpu": self.run.last_cpu, "wall": wall, "steps": r["run"]["steps"],
                    "newton": t.get("static_solve", {}).get("newton_iterations", 0),
                    "rest": r["run"]["rest_area_growth"],
                    "verdict": r["verification"]["verdict"], "cycles": len(r["cycles"])})
            self.run.say(f"whole fit, pair {pair + 1}/{pairs}: damped {runs['dynamic'][-1]['cpu']:.1f} s, "
                         f"static {runs['static'][-1]['cpu']:.1f} s of CPU")
        self.results["whole_fit"] = {"runs": runs, "flags": flags, "pairs": pairs}

    def scenes(self, demo):
        if os.path.isdir(SHARED):
            return [
                bench_sim.Scene("shirt", "shared", os.path.join(self.run.path("poses-slim_tpose"), "poses.json"),
                                os.path.join(CUSTOMERS, "slim-shirt", "garment-spec.json"), None,
                                os.path.join(CUSTOMERS, "slim-shirt", "seams.json"), ["slim_tpose", "slim_apose"]),
                bench_sim.Scene("dress", "shared", os.path.join(self.run.path("poses-slim_apose"), "poses.json"),
                                os.path.join(CUSTOMERS, "slim-dress", "garment-spec.json"),
                                os.path.join(CUSTOMERS, "slim-dress", "extend.json"),
                                os.path.join(CUSTOMERS, "slim-dress", "seams.json"), ["slim_apose", "slim_armsup"]),
            ]
        self.notes.append("simulate-adapt: ../shared/avatars not found, so the demo shirt on the generated body "
                          "stands in for the shared shirt, and there is no dress row")
        return [bench_sim.Scene("demo shirt", "generated", os.path.join(demo, "poses", "poses.json"),
                                os.path.join(CUSTOMERS, "demo", "garment-spec.json"), None,
                                os.path.join(CUSTOMERS, "demo", "seams.json"), ["apose", "tpose"])]

    def simulate(self, demo):
        if os.path.isdir(SHARED):
            for reference in ("slim_tpose", "slim_apose"):
                if not os.path.exists(os.path.join(self.run.path(f"poses-{reference}"), "poses.json")):
                    self.register_for(reference)
        sim = bench_sim.SimBench(self.run, self.scenes(demo), self.quick, self.results, self.notes)
        sim.execute(RESERVE_S)
        seen = []
        for s in sim.measured.values():
            if any(s is t for t in seen):
                continue
            seen.append(s)
            m = s["measurement"]
            self.row("simulate-adapt", f"{s['scene']}, {s['vertices']} vertices, {s['motion']}, settle cap "
                     f"{s['cap']}{', ' + ' '.join(s['args']) if s['args'] else ''}", 1, m,
                     f"{s['steps']} steps ({s['settle_steps']} settling, {s['rejected_steps']} rejected), "
                     f"{s['steps_per_s']:.2f} steps/s, {s['cg_iterations']} CG iterations, {s['adaptations']} "
                     f"adaptations, solver {s['solver']}; over the key poses: max stretch {s['max_stretch']:.3f}, "
                     f"p99 {s['p99_stretch']:.3f}, deepest penetration {1000 * s['penetration_m']:.1f} mm, rest "
                     f"area x{s['rest_area_growth']:.3f}, settled: {'yes' if s['all_settled'] else 'no'}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bin", default=os.environ.get("GP_BIN", os.path.join(ROOT, "build", "bin")),
                   help="folder with the built stages (default: $GP_BIN, else build/bin)")
    p.add_argument("--out", default=os.path.join(ROOT, "BENCHMARKS.md"), help="Markdown file to write")
    p.add_argument("--plots", default=os.path.join(ROOT, "benchmarks"), help="folder for the PNG plots (regenerated)")
    p.add_argument("--repeats", type=int, default=3, help="runs per measurement of the fast stages (median reported)")
    p.add_argument("--budget", type=float, default=750.0, help="wall time the whole benchmark keeps to [s]")
    p.add_argument("--quick", action="store_true", default=os.environ.get("GP_BENCH_QUICK") == "1",
                   help="reduced run for development: one repeat, ~1,100 vertices only, fewer points "
                        "(also GP_BENCH_QUICK=1)")
    args = p.parse_args()
    if args.quick:
        args.repeats = 1
        args.budget = min(args.budget, 240.0)

    started = datetime.datetime.now(datetime.timezone.utc)
    load_before = load_average()
    work = tempfile.mkdtemp(prefix="gp_bench_")
    run = bench_run.Runner(os.path.abspath(args.bin), work, args.budget, args.repeats)
    run.say(f"binaries {run.bin}, budget {args.budget:.0f} s{', quick mode' if args.quick else ''}, "
            f"load average {load_before}")
    bench = Bench(run, args.quick)
    t0 = time.perf_counter()
    try:
        bench.register_check()
        bench.make_avatar()
        bench.interp_poses()
        designed = bench.make_garment()
        demo = bench.demo_fit()
        bench.export_rest(designed, demo)
        bench.whole_fit(demo)
        bench.simulate(demo)
        plots = bench_plots.write_all(bench, args.plots)
    except bench_run.StageFailed as e:
        print(f"bench: error: {e}", file=sys.stderr)
        shutil.rmtree(work, ignore_errors=True)
        return 1
    meta = {
        "date": started.strftime("%Y-%m-%d %H:%M UTC"), "machine": machine(), "repeats": args.repeats,
        "budget_s": args.budget, "quick": args.quick, "load_before": load_before, "load_after": load_average(),
        "total_s": time.perf_counter() - t0, "processes": run.processes,
        "plots_rel": os.path.relpath(os.path.abspath(args.plots), os.path.dirname(os.path.abspath(args.out))),
    }
    bench_report.write(args.out, bench, meta, plots)
    shutil.rmtree(work, ignore_errors=True)
    run.say(f"wrote {args.out} and {len(plots)} plots in {args.plots}; total {meta['total_s']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
