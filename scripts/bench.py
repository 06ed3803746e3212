#!/usr/bin/python3
"""Benchmarks of the pipeline's stages, written to BENCHMARKS.md.

Each benchmark runs a stage as a user would (a separate process), several
times, and reports the median wall time, the spread, and figures the stage
writes into its timing.json / report.json. Machine, thread count and date are
stated. Inputs are generated bodies (always available) and the shared
registered avatars where ../shared/avatars exists.
"""
import argparse
import datetime
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
SHARED = os.path.abspath(os.path.join(ROOT, "..", "shared", "avatars"))


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


class Runner:
    def __init__(self, bin_dir, work, repeats):
        self.bin = bin_dir
        self.work = work
        self.repeats = repeats

    def tool(self, name):
        return os.path.join(self.bin, name)

    def run_once(self, args, out_dir):
        if os.path.exists(out_dir):
            shutil.rmtree(out_dir)
        t0 = time.perf_counter()
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        r = subprocess.run(args + ["--out", out_dir, "--quiet"], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if r.returncode != 0:
            raise RuntimeError(f"{' '.join(args)} exited {r.returncode}: {r.stderr.strip()}")
        peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        return wall, max(peak_kib, before)

    def measure(self, args, name):
        """Median over repeats of wall time; returns (median, min, max, out_dir, peak MiB)."""
        out_dir = os.path.join(self.work, name)
        times = []
        for _ in range(self.repeats):
            wall, _peak = self.run_once(args, out_dir)
            times.append(wall)
        # Peak resident memory of one more run, measured alone through /usr/bin/time's
        # equivalent: getrusage of a fresh child process group is cumulative, so use
        # a dedicated subprocess that reports its own child's maximum.
        peak = peak_memory_mib(args + ["--out", out_dir + "-mem", "--quiet"])
        return statistics.median(times), min(times), max(times), out_dir, peak


def peak_memory_mib(args):
    code = ("import resource,subprocess,sys;"
            "r=subprocess.run(sys.argv[1:],capture_output=True);"
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss if r.returncode==0 else -1)")
    out = subprocess.run([sys.executable, "-c", code] + args, capture_output=True, text=True)
    kib = int(out.stdout.strip() or -1)
    return kib / 1024.0 if kib > 0 else float("nan")


def load_json(path):
    with open(path) as f:
        return json.load(f)


def bench_register_check(run, rows, notes):
    if not os.path.isdir(SHARED):
        notes.append("register-check on the shared avatars: skipped (../shared/avatars not found)")
        return
    poses = [os.path.join(SHARED, f"slim_{p}.ply") for p in ("apose", "tpose", "armsup", "armsbent")]
    for threads in (1, 2):
        med, lo, hi, out, mem = run.measure(
            [run.tool("register-check"), *poses, "--threads", str(threads)], f"rc{threads}")
        t = load_json(os.path.join(out, "timing.json"))
        rows.append(("register-check", f"shared body, 4 poses x 27,578 vertices, self-intersections on",
                     threads, med, lo, hi, mem,
                     f"read {t['read_s']:.3f} s, checks {t['checks_s']:.3f} s, "
                     f"self-intersections {t['self_intersections_s']:.3f} s (target < 2 s)"))


def bench_interp_poses(run, rows, notes):
    if not os.path.isdir(SHARED):
        notes.append("interp-poses on the shared avatars: skipped (../shared/avatars not found)")
        return
    poses = [os.path.join(SHARED, f"slim_{p}.ply") for p in ("apose", "armsup")]
    motion = os.path.join(ROOT, "testdata", "motions", "apose_armsup.json")
    for method in ("nonlinear", "linear"):
        med, lo, hi, out, mem = run.measure(
            [run.tool("interp-poses"), *poses, "--motion", motion, "--method", method, "--keys-only",
             "--threads", "1"], f"interp-{method}")
        t = load_json(os.path.join(out, "timing.json"))
        r = load_json(os.path.join(out, "report.json"))
        summary = r["summary"]
        detail = (f"factorization {t['factorization_ms']:.1f} ms, {t['ms_per_frame_mean']:.2f} ms/frame wall "
                  f"({t['cpu_ms_per_frame_mean']:.2f} ms CPU; target < 15 ms), 61 frames; edge-length "
                  f"excursion beyond the keys' range max {100 * summary['edge_excess_max']:.1f} %, volume "
                  f"{100 * summary['volume_excess_max']:.2f} %")
        if "linear_vs_nonlinear" in summary:
            d = summary["linear_vs_nonlinear"]
            detail += (f"; linear baseline against it: edge deviation max {100 * d['edge_deviation_max']:.0f} % "
                       f"/ mean {100 * d['edge_deviation_mean']:.1f} %, volume {100 * d['volume_error']:.1f} %, "
                       f"vertex distance {d['vertex_distance_max_m']:.3f} m")
        rows.append(("interp-poses", f"shared body A-pose -> arms up, 60 steps, {method}", 1, med, lo, hi, mem,
                     detail))


def bench_make_garment(run, rows, notes):
    if not os.path.isdir(SHARED):
        notes.append("make-garment on the shared avatars: skipped (../shared/avatars not found)")
        return
    rc = os.path.join(run.work, "poses")
    subprocess.run([run.tool("register-check"), SHARED, "--reference", "slim_apose", "--out", rc, "--force",
                    "--quiet", "--no-self-intersections"], check=True)
    for name in ("shirt", "dress"):
        spec = os.path.join(ROOT, "pipelines", "specs", f"{name}.json")
        med, lo, hi, out, mem = run.measure(
            [run.tool("make-garment"), spec, "--poses", os.path.join(rc, "poses.json")], f"garment-{name}")
        r = load_json(os.path.join(out, "report.json"))
        q = r["quality"]
        t = load_json(os.path.join(out, "timing.json"))
        phases = ", ".join(f"{k[:-2]} {v:.2f} s" for k, v in t.items() if k.endswith("_s") and k != "total_s")
        g = load_json(os.path.join(out, "garment.json"))
        rows.append(("make-garment", f"{name} on the shared body, {g['mesh']['vertex_count']} garment vertices", 1,
                     med, lo, hi, mem,
                     f"{phases}; min angle > 20 deg for {100 * q['fraction_min_angle_over_20_deg']:.1f} % of "
                     f"triangles, edges within 30 % for {100 * q['fraction_edges_within_30_percent']:.1f} %, "
                     f"offset error max {1000 * q['offset_max_error']:.2f} mm (target < 3 s)"))
        if name == "dress":
            ext = os.path.join(ROOT, "pipelines", "specs", "dress-extend.json")
            med, lo, hi, eout, mem = run.measure(
                [run.tool("extend-boundary"), os.path.join(out, "garment.json"), ext], "extend-dress")
            e = load_json(os.path.join(eout, "report.json"))["extension"]
            rows.append(("extend-boundary", "dress waist -> skirt hem on the shared body", 1, med, lo, hi, mem,
                         f"hem girth {e['new_girth']:.3f} m"))


def bench_make_avatar(run, rows, notes):
    poses = "apose,tpose,armsup,armsforward,elbowsbent,stepforward"
    for res in ("default", "small"):
        med, lo, hi, out, mem = run.measure(
            [run.tool("make-avatar"), "--poses", poses, "--resolution", res], f"avatar-{res}")
        r = load_json(os.path.join(out, "report.json"))
        t = load_json(os.path.join(out, "timing.json"))
        phases = ", ".join(f"{k} {v:.2f} s" for k, v in t.items() if isinstance(v, float) and k != "total")
        rows.append(("make-avatar", f"default body, 6 poses, {r['mesh']['vertex_count']} vertices ({res})", 1,
                     med, lo, hi, mem,
                     f"largest girth error {1000 * r['max_girth_error_m']:.2f} mm, largest volume change between "
                     f"poses {100 * r['max_pairwise_volume_change']:.2f} % (target < 2 s at default); {phases}"))


def generated_fit(run, name):
    """Runs the demo customer's first stages once, for the later benches."""
    out = os.path.join(run.work, name)
    subprocess.run(["make", "--no-print-directory", "-s", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
                    f"CUSTOMER={os.path.join(ROOT, 'pipelines', 'customers', 'demo')}", f"OUT={out}",
                    f"BIN={run.bin}", f"{out}/garment/report.json"], check=True, capture_output=True)
    return out


def bench_simulate_adapt(run, rows, notes):
    fit = generated_fit(run, "demo-fit")
    motion = os.path.join(ROOT, "pipelines", "customers", "demo", "motion.json")
    args = [run.tool("simulate-adapt"), "--poses", os.path.join(fit, "poses", "poses.json"), "--motion", motion,
            "--garment", os.path.join(fit, "garment", "garment.json"), "--threads", "1"]
    for label, extra in (("adapt", []), ("no-adapt", ["--no-adapt"])):
        med, lo, hi, out, mem = run.measure(args + extra, f"sim-{label}")
        r = load_json(os.path.join(out, "report.json"))
        t = load_json(os.path.join(out, "timing.json"))
        ms = t["ms_per_step"]
        keys = r["key_poses"]
        worst = max(k["max_stretch"] for k in keys)
        p99 = max(k["p99_stretch"] for k in keys)
        pen = max(k["deepest_penetration_m"] for k in keys)
        steps = keys[-1]["steps"]
        rows.append(("simulate-adapt",
                     f"demo shirt on the generated body, {r['counts']['garment_vertices']} vertices, "
                     f"A -> T -> arms up -> A, 30 frames per transition, {label}", 1, med, lo, hi, mem,
                     f"{steps} steps, {t['steps_per_s']:.1f} steps/s; ms per step: forces "
                     f"{ms['forces_assembly']:.2f}, factorization {ms['factorization']:.2f}, solve {ms['solve']:.2f}, "
                     f"collisions {ms['collisions']:.2f}, adaptation {ms['adaptation']:.2f}; over all key poses: "
                     f"max stretch {worst:.3f}, p99 {p99:.3f}, deepest penetration {1000 * pen:.1f} mm, rest area "
                     f"x{keys[-1]['rest_area_growth']:.3f}"))
    notes.append("The paper's published figures (Wolff et al. 2023, 12-core 2.7 GHz CPU): 1.70 frames/s at 3,926 "
                 "garment vertices and 7.82 frames/s at 1,103, one frame being one simulation step.")


def bench_export_rest(run, rows, notes):
    fit = os.path.join(run.work, "sim-adapt")
    garment = os.path.join(run.work, "demo-fit", "garment", "garment.json")
    seams = os.path.join(ROOT, "pipelines", "customers", "demo", "seams.json")
    for label, limits in (("looser 5 % / 10 %", ["--p95-limit", "0.05", "--max-limit", "0.1"]),
                          ("default 2 % / 5 %", []),
                          ("tighter 1 % / 3 %", ["--p95-limit", "0.01", "--max-limit", "0.03"])):
        med, lo, hi, out, mem = run.measure(
            [run.tool("export-rest"), os.path.join(fit, "rest.ply"), "--garment", garment, "--seams", seams,
             "--body", os.path.join(run.work, "demo-fit", "poses", "poses.json"), *limits],
            "export-" + label.split()[0])
        sm = load_json(os.path.join(out, "report.json"))["summary"]
        rows.append(("export-rest", f"demo shirt rest shape, side and shoulder seams, limit {label}", 1,
                     med, lo, hi, mem,
                     f"{sm['pieces']} pieces, {sm['added_cuts']} added cuts, seam length {sm['total_seam_length']:.2f} m, "
                     f"worst p95 {100 * sm['worst_p95_error']:.2f} %, max {100 * sm['worst_max_error']:.2f} %, "
                     f"limit met: {'yes' if sm['meets_distortion_limit'] else 'no'}"))


BENCHES = [bench_register_check, bench_make_avatar, bench_interp_poses, bench_make_garment,
           bench_simulate_adapt, bench_export_rest]


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--bin", required=True, help="folder with the built stages")
    p.add_argument("--out", default=os.path.join(ROOT, "BENCHMARKS.md"), help="Markdown file to write")
    p.add_argument("--plots", default=os.path.join(ROOT, "bench-out"), help="folder for plots (regenerated)")
    p.add_argument("--repeats", type=int, default=5, help="runs per measurement (median reported)")
    args = p.parse_args()

    work = tempfile.mkdtemp(prefix="gp_bench_")
    run = Runner(args.bin, work, args.repeats)
    rows, notes = [], []
    for bench in BENCHES:
        bench(run, rows, notes)
    shutil.rmtree(work, ignore_errors=True)

    lines = [
        "# Benchmarks",
        "",
        f"Generated by `make bench` on {datetime.date.today().isoformat()}; machine: {machine()}.",
        f"Each figure is the median of {args.repeats} runs of the stage as a separate process "
        "(min and max beside it); peak memory is the resident-set maximum of one run.",
        "",
        "| stage | case | threads | median [s] | min [s] | max [s] | peak memory [MiB] | breakdown |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    for stage, case, threads, med, lo, hi, mem, detail in rows:
        lines.append(f"| {stage} | {case} | {threads} | {med:.3f} | {lo:.3f} | {hi:.3f} | {mem:.0f} | {detail} |")
    if notes:
        lines += ["", "Notes:", ""] + [f"- {n}" for n in notes]
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"bench: wrote {args.out}")


if __name__ == "__main__":
    main()
