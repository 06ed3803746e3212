"""BENCHMARKS.md from the results of scripts/bench.py."""
import math
import os
import statistics

PAPER = [(3926, 1.70), (1103, 7.82)]  # Wolff et al. 2023: garment vertices, frames/s on 12 cores at 2.7 GHz
PHASES = [("forces_assembly", "forces + assembly"), ("factorization", "factorization"), ("solve", "solve"),
          ("collisions", "collisions"), ("adaptation", "adaptation"), ("body", "body interpolation")]
# The shirt's full customer motion on the shared body (T -> A -> arms up -> arms
# bent -> T), measured outside the benchmark with the default options: 36.0 s
# on one thread (`--workers 1`), 29.4-29.8 s in three runs with two (the
# default); the same 1,128 steps and outputs with both. Time steps 1 % longer
# and shorter took 1,008 and 1,032 steps (26.9 and 27.7 s with two threads).
FULL_RUN = {"vertices": 3829, "steps": 1128, "seconds_one_thread": 36, "seconds_two_threads": 29.6,
            "dt_plus_minus_1pct_steps": (1008, 1032)}
ROUNDING_M = 1e-5  # [m]: mesh differences below this count as rounding
PARAM_TITLES = {"dt": ("time step --dt", "s"), "adapt_every": ("adaptation interval --adapt-every", "steps"),
                "cg_tolerance": ("solver tolerance --cg-tolerance", "relative residual"),
                "vertices": ("resolution (make-garment resolution.vertex_count)", "garment vertices")}


def fmt_value(key, v):
    if key == "cg_tolerance":
        return f"{v:.0e}"
    if key == "dt":
        return f"{v:g}"
    return f"{v:,}" if isinstance(v, int) else f"{v:g}"


def phase_cells(s):
    """Per-phase ms per step, the rest of the step ("other") and the total."""
    ms = s["ms_per_step"]
    total = 1000.0 / s["steps_per_s"] if s["steps_per_s"] > 0 else math.nan
    known = [ms.get(k, math.nan) for k, _ in PHASES]
    other = total - sum(v for v in known if not math.isnan(v))
    return [f"{v:.2f}" for v in known] + [f"{other:.2f}"], total


def settled(s):
    return "yes" if s["all_settled"] else "no"


def full_motion_text():
    """Why the benchmark does not run the customers' full motions."""
    r = FULL_RUN
    return (f"A full customer motion is four transitions of 60 frames ({4 * 60} steps) plus settling at each key "
            f"pose until the cloth and the rest shape stop changing; the shirt at {r['vertices']:,} vertices "
            f"through T, A, arms up, arms bent and T took {r['steps']:,} steps, {r['seconds_one_thread']} s on one "
            f"thread and {r['seconds_two_threads']} s with two (measured outside this benchmark), too long for its "
            f"budget. Its step count is sensitive to "
            f"perturbations that leave the physics alone: time steps 1 % longer and shorter took "
            f"{r['dt_plus_minus_1pct_steps'][0]:,} and {r['dt_plus_minus_1pct_steps'][1]:,} steps.")


def sim_section(lines, results, meta, plot):
    rows = results.get("sim_breakdown", [])
    lines += ["## simulate-adapt: time per step", ""]
    if not rows:
        lines += ["No simulation row was measured (see the notes).", ""]
        return
    lines += [
        f"Each garment moves through one transition of {results['sim_frames']} frames (one simulation step per "
        "frame, adaptation every 8 steps and at the key pose) and stops there: `--settle-max-steps 0`, so these are "
        "steps of a moving body, the situation of the paper's frames per second. " + full_motion_text() +
        " One thread (`--workers 1`), the default solver and settings. Milliseconds per step: each run's mean over "
        "its steps (timing.json), median over the runs; `other` is the rest of the step (1000 / steps per second minus the "
        "phases: rejected and retried steps, set-up spread over the steps, stepping logic); steps/s is the stage's "
        "own figure (steps over the stepping time, median over the runs); the wall time adds start-up and output.",
        "",
        "| garment, motion | vertices | runs | wall median [s] | steps | steps/s | " +
        " | ".join(f"{t} [ms]" for _, t in PHASES) + " | other [ms] | total [ms/step] | rejected steps | "
        "max stretch | p99 stretch |",
        "| --- | ---: | ---: | ---: | ---: | ---: | " + " | ".join("---:" for _ in PHASES) +
        " | ---: | ---: | ---: | ---: | ---: |",
    ]
    for s in rows:
        cells, total = phase_cells(s)
        lines.append(f"| {s['scene']}, {s['motion']} | {s['vertices']:,} | {s['runs']} | {s['median_s']:.1f} | "
                     f"{s['steps']} | {s['steps_per_s']:.2f} | " + " | ".join(cells) +
                     f" | {total:.1f} | {s['rejected_steps']} | {s['max_stretch']:.3f} | {s['p99_stretch']:.3f} |")
    for vertices, fps in PAPER:
        lines.append(f"| **the paper's figure** (Wolff et al. 2023: their garment, 12 cores at 2.7 GHz) | {vertices:,} "
                     f"| | | | **{fps:.2f} frames/s** | " + " | ".join("" for _ in PHASES) + " | | | | | |")
    for key, why in results.get("sim_breakdown_failed", {}).items():
        lines.append(f"| {key}: failed: {why} | | | | | | " + " | ".join("" for _ in PHASES) + " | | | | | |")
    lines += ["", "The paper's figures are quoted from the paper (one frame is one simulation step there), not "
              "measured here; ours use one core.", ""]
    lines += plot("sim_breakdown.png") + plot("sim_speed.png")
    threads_section(lines, results)


def threads_section(lines, results):
    rows = results.get("sim_threads", [])
    if not rows:
        return
    lines += [
        "### Two threads", "",
        "The same motions with `--workers 2`, simulate-adapt's default: a second thread prepares the next body frame "
        "(interpolation, pin targets, collision tree) and computes each adaptation while the cloth steps (the "
        "adaptation is applied `--adaptation-lag` steps after its positions, 2 by default, with one thread or two "
        "alike). Steps/s: median over the runs; waiting: what the stepping thread spent waiting for the other.",
        "",
        "| garment, motion | vertices | steps/s, one thread | steps/s, two threads | ratio | waiting [ms/step] | "
        "outputs against one thread |",
        "| --- | ---: | ---: | ---: | ---: | ---: | --- |",
    ]
    for r in rows:
        one, two = r["one"], r["two"]
        waiting = two["ms_per_step"].get("waiting_for_worker", math.nan)
        verdict = "byte-identical" if r["diff"]["byte_identical"] else f"differ by up to {r['diff']['max_m']:.3g} m"
        lines.append(f"| {one['scene']}, {one['motion']} | {one['vertices']:,} | {one['steps_per_s']:.2f} | "
                     f"{two['steps_per_s']:.2f} | {two['steps_per_s'] / one['steps_per_s']:.2f} | {waiting:.2f} | "
                     f"{verdict} |")
    lines.append("")


def diff_text(d):
    verdict = "byte-identical" if d["byte_identical"] else "not byte-identical"
    per_file = ", ".join(f"{f} {m:.2g} m" for f, m, _ in d["files"])
    return f"{verdict}; largest vertex distance {d['max_m']:.3g} m ({per_file})"


def culling_section(lines, results, plot):
    c = results.get("culling")
    lines += ["## Collision culling", ""]
    if not c:
        lines += ["Not measured (see the notes).", ""]
        return
    w, wo, d = c["with"], c["without"], c["diff"]
    lines += [
        f"{w['scene']}, {w['vertices']:,} vertices, {w['motion']}, settle cap {w['cap']}: body faces farther than "
        "`--reach` from the garment are dropped once per motion. Without culling: `--reach 10` keeps every face.",
        "",
        "| culling | body faces queried | runs | wall median [s] | steps | steps/s | " +
        " | ".join(f"{t} [ms]" for _, t in PHASES) + " | other [ms] | total [ms/step] | max stretch | p99 stretch | "
        "area > 1.1 [%] | deepest penetration [mm] |",
        "| --- | ---: | ---: | ---: | ---: | ---: | " + " | ".join("---:" for _ in PHASES) +
        " | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    cases = [("with (`--reach 0.15`, default)", w)]
    if "mid" in c:
        cases.append(("with (`--reach 0.3`)", c["mid"]))
    cases.append(("without (`--reach 10`)", wo))
    for label, s in cases:
        cells, total = phase_cells(s)
        lines.append(f"| {label} | {s['body_faces_kept']:,} of {s['body_faces']:,} | {s['runs']} | "
                     f"{s['median_s']:.1f} | {s['steps']} | {s['steps_per_s']:.2f} | " + " | ".join(cells) +
                     f" | {total:.1f} | {s['max_stretch']:.4f} | "
                     f"{s['p99_stretch']:.4f} | {100 * s['area_above_limit']:.2f} | {1000 * s['penetration_m']:.2f} |")
    lines += ["", f"Results unchanged? Output meshes with the default culling against none: {diff_text(d)}."]
    if "mid" in c:
        lines += ["", f"`--reach 0.3` against none: {diff_text(c['mid_diff'])}."]
    if "fixed" in c:
        on, off, fd = c["fixed"]
        lines += ["", f"The same pair with a fixed rest shape (`--no-adapt`): {on['median_s']:.1f} s with culling, "
                  f"{off['median_s']:.1f} s without; meshes {diff_text(fd)}."]
        if fd["max_m"] < ROUNDING_M and d["max_m"] >= ROUNDING_M:
            lines[-1] += (" So the culling by itself changes the simulation only at rounding level (under "
                          f"{ROUNDING_M:g} m); with adaptation (stretch clipping and stitching every few steps) such "
                          "differences grow over the motion into the distances above.")
        elif fd["max_m"] >= ROUNDING_M:
            lines[-1] += (f" The culling changes the simulation itself by more than {ROUNDING_M:g} m: a dropped "
                          "body face mattered.")
    if c.get("repeat"):
        lines += ["", f"The default configuration run twice: {diff_text(c['repeat'])}" +
                  ("; so a difference above comes from the culling, not from run-to-run noise."
                   if c["repeat"]["byte_identical"] else "; runs are not reproducible, so differences above include "
                   "run-to-run noise.")]
    lines.append("")


def tradeoff_section(lines, results, plot):
    curves = results.get("tradeoff", {})
    lines += ["## Trade-offs at about 1,100 garment vertices", ""]
    if not curves:
        lines += ["Not measured (see the notes).", ""]
        return
    any_s = next(p[1] for pts in curves.values() for p in pts if "failed" not in p[1])
    d = results.get("tradeoff_defaults", {})
    lines += [
        f"{any_s['scene']}, {any_s['motion']}, " + (
            f"then settling at each key pose up to {any_s['cap']} steps (the cap the benchmark could afford, planned "
            "from the measured speed)" if any_s["cap"] > 0 else
            "no settling (settle cap 0: the time left after the rows above, planned from the measured speed, "
            "affords no settling steps for all these runs)") + "; one parameter varied at a time from the "
        f"stage's defaults (dt {d.get('dt', math.nan):g} s, adapt every {d.get('adapt_every', math.nan)} steps, CG "
        f"tolerance {d.get('cg_tolerance', math.nan):g}, ~1,100 vertices). Residual error over all "
        "key poses after adaptation: the 99th-percentile and maximum principal stretch, the area fraction above "
        "1+delta (1.1) and the deepest penetration into the body; the time is the wall time of the whole run, a "
        "finished fit only where `settled` says yes.",
        "",
    ]
    for key, points in curves.items():
        title, unit = PARAM_TITLES[key]
        lines += [f"**{title}** [{unit}]", "",
                  "| value | vertices | runs | wall [s] | steps | steps/s | p99 stretch | max stretch | area > 1.1 [%] | "
                  "deepest penetration [mm] | rest area growth | settled |",
                  "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
        for v, s in points:
            if "failed" in s:
                lines.append(f"| {fmt_value(key, v)} | | | | | | failed: {s['failed']} | | | | | |")
                continue
            lines.append(f"| {fmt_value(key, v)} | {s['vertices']:,} | {s['runs']} | {s['median_s']:.1f} | {s['steps']} | "
                         f"{s['steps_per_s']:.2f} | {s['p99_stretch']:.4f} | {s['max_stretch']:.4f} | "
                         f"{100 * s['area_above_limit']:.2f} | {1000 * s['penetration_m']:.2f} | "
                         f"{s['rest_area_growth']:.4f} | {settled(s)} |")
        lines.append("")
    lines += plot("tradeoffs.png")


def interp_section(lines, results, plot):
    rows = results.get("interp", [])
    if not rows:
        return
    lines += ["## interp-poses: nonlinear against linear", "",
              "Shared body, A-pose -> arms up, 60 steps, one thread. Shape error: largest edge-length and volume "
              "excursion beyond the range spanned by the two key poses.", "",
              "| method | runs | ms per frame | edge-length excursion [%] | volume excursion [%] |",
              "| --- | ---: | ---: | ---: | ---: |"]
    for r in rows:
        lines.append(f"| {r['method']} | {r['runs']} | {r['ms_per_frame']:.2f} | {100 * r['edge_excess']:.1f} | "
                     f"{100 * r['volume_excess']:.2f} |")
    lines.append("")
    lines += plot("interp.png")


def export_section(lines, results, plot):
    rows = results.get("export", [])
    if not rows:
        return
    lines += ["## export-rest: distortion limit against pieces, seams and time", "",
              "Rest shape = the garment as designed (make-garment output; the dress with its extension), so that "
              "the rows do not depend on how far the simulation ran; the customers' seams. Limit: principal-stretch "
              "error allowed on 95 % of the area / everywhere.", "",
              "| garment | vertices | limit p95 / max | runs | median [s] | pieces | seam length [m] | limit met |",
              "| --- | ---: | --- | ---: | ---: | ---: | ---: | --- |"]
    for r in rows:
        lines.append(f"| {r['garment']} | {r['vertices']:,} | {r['label']} {100 * r['p95_limit']:.0f} % / "
                     f"{100 * r['max_limit']:.0f} % | {r['runs']} | {r['median_s']:.2f} | {r['pieces']} | "
                     f"{r['seam_length']:.2f} | {'yes' if r['met'] else 'no'} |")
    lines.append("")
    lines += plot("export.png")


def memory_rows(bench):
    """Largest peak resident memory per stage, with the case it came from."""
    worst = {}
    for stage, case, _threads, m, _detail in bench.rows:
        if stage not in worst or m.peak_mib > worst[stage][1]:
            worst[stage] = (case, m.peak_mib)
    return worst


def memory_section(lines, bench, plot):
    lines += ["## Peak memory per stage", "",
              "Largest resident-set peak of one stage process over all its runs here (wait4's ru_maxrss of that "
              "process alone).", "",
              "| stage | peak memory [MiB] | case |", "| --- | ---: | --- |"]
    for stage, (case, mib) in memory_rows(bench).items():
        lines.append(f"| {stage} | {mib:.0f} | {case} |")
    lines.append("")
    lines += plot("memory.png")


# Sections written by hand in benchmarks/<file>: measurements a benchmark run
# cannot make itself (ratios against an older binary, whole fits of the
# example customers, strategies compared), kept beside the generated ones so
# that rerunning make bench never loses them. (file, heading, level)
HAND_WRITTEN = {
    "changes": ("changes.md", "Changes measured against the binary before them", "###"),
    "independence": ("independence.md", "simulate-adapt: independence of numerical parameters and pose order", "##"),
    "cutters": ("cutters.md", "export-rest: cutter strategies on adapted rest shapes", "###"),
}


def split_sections(text):
    """The text's level-2 sections in order: (heading, lines with the heading
    line first); what comes before the first heading is left out."""
    sections = []
    for line in text.splitlines():
        if line.startswith("## "):
            sections.append((line[3:].strip(), [line]))
        elif sections:
            sections[-1][1].append(line)
    return sections


def carried_over(old_text, written_lines):
    """The level-2 sections of the old BENCHMARKS.md text that the new one does
    not write (measurements written there by hand, not by this script), in
    their old order, each as its lines with trailing blank lines trimmed.
    Rerunning make bench must never lose a measurement."""
    written = {line[3:].strip() for line in written_lines if line.startswith("## ")}
    kept = []
    for heading, body in split_sections(old_text):
        if heading in written:
            continue
        while body and not body[-1].strip():
            body.pop()
        kept.append(body)
    return kept


def whole_fit_section(lines, results):
    """The demo's whole fit with both solvers, interleaved (bench.py, whole_fit)."""
    w = results.get("whole_fit")
    if not w:
        return
    runs = w["runs"]
    lines += ["## simulate-adapt: a whole fit, damped settling against the static solve", "",
              f"The demo customer's `simulate-adapt` (fit and verification, `{' '.join(w['flags'])}`, "
              f"`--workers 1`), `--solver dynamic` and `--solver static` in {w['pairs']} interleaved pair(s), the "
              "order swapped every pair; CPU is the process's user and system time. The ratio is the median of "
              "the pairs' ratios (issue 45's target: 0.3).", "",
              "| solver | runs | median CPU [s] | median wall [s] | fit: time steps | fit: Newton iterations | rest area | "
              "cycles | verification |",
              "| --- | ---: | ---: | ---: | ---: | ---: | --- | ---: | --- |"]
    for solver, label in (("dynamic", "damped settling"), ("static", "static solve")):
        rs = runs[solver]
        med = lambda key: statistics.median(r[key] for r in rs)  # noqa: E731
        verdicts = sorted({r["verdict"] for r in rs})
        lines.append(f"| {label} | {len(rs)} | {med('cpu'):.1f} | {med('wall'):.1f} | {med('steps'):.0f} | "
                     f"{med('newton'):.0f} | x{rs[-1]['rest']:.4f} | {rs[-1]['cycles']} | {', '.join(verdicts)} |")
    ratios = [s["cpu"] / d["cpu"] for d, s in zip(runs["dynamic"], runs["static"]) if d["cpu"] > 0]
    if ratios:
        lines += ["", f"CPU of the static solve over the damped settling: {statistics.median(ratios):.2f} "
                      f"(pairs: {', '.join(f'{x:.2f}' for x in ratios)})."]
    lines.append("")


def hand_section(lines, folder, key):
    """The hand-written section key of HAND_WRITTEN, if its file has text."""
    name, heading, level = HAND_WRITTEN[key]
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        return
    with open(path) as f:
        text = f.read().strip()
    if text:
        lines += [f"{level} {heading}", "", text, ""]


def write(path, bench, meta, plots):
    available = set(plots)

    def plot(name):
        if name not in available:
            return []
        return [f"![{name}]({meta['plots_rel']}/{name})", ""]

    lines = [
        "# Benchmarks",
        "",
        f"Generated by `make bench` (scripts/bench.py) on {meta['date']}; machine: {meta['machine']}. "
        f"Every stage runs as its own process with `--threads 1` unless the threads column says otherwise. "
        f"The machine is shared: load average (1/5/15 min) {meta['load_before']} before and {meta['load_after']} "
        f"after the run, so absolute times carry that noise. Whole benchmark: {meta['total_s']:.0f} s, "
        f"{meta['processes']} processes, within a budget of {meta['budget_s']:.0f} s"
        f"{' (quick mode: reduced settings)' if meta['quick'] else ''}.",
        "",
        f"Fast stages: median of {meta['repeats']} runs (min and max in the last table). Simulations: median of the "
        "runs the time allowed (the runs column), at least one. Sections measured by hand (whole fits, ratios "
        "against other binaries) are kept from the file as it was; their own text says when and how.",
        "",
    ]
    hand = os.path.join(os.path.dirname(os.path.abspath(path)), meta["plots_rel"])
    sim_section(lines, bench.results, meta, plot)
    hand_section(lines, hand, "changes")
    hand_section(lines, hand, "independence")
    culling_section(lines, bench.results, plot)
    whole_fit_section(lines, bench.results)
    tradeoff_section(lines, bench.results, plot)
    interp_section(lines, bench.results, plot)
    export_section(lines, bench.results, plot)
    hand_section(lines, hand, "cutters")
    memory_section(lines, bench, plot)
    # Sections written into BENCHMARKS.md by hand (whole fits, ratios against
    # other binaries, build times) stay, before the table of runs.
    old_text = ""
    if os.path.exists(path):
        with open(path) as f:
            old_text = f.read()
    for body in carried_over(old_text, lines + ["## Every measured run"]):
        lines += body + [""]
    lines += ["## Every measured run", "",
              "| stage | case | threads | runs | median [s] | min [s] | max [s] | peak memory [MiB] | details |",
              "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    for stage, case, threads, m, detail in bench.rows:
        lines.append(f"| {stage} | {case} | {threads} | {m.runs} | {m.median:.3f} | {m.lo:.3f} | {m.hi:.3f} | "
                     f"{m.peak_mib:.0f} | {detail} |")
    skipped = bench.results.get("sim_skipped", [])
    notes = list(bench.notes) + [f"simulate-adapt run skipped or stopped: {s}" for s in skipped]
    if notes:
        lines += ["", "Notes:", ""] + [f"- {n}" for n in notes]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
