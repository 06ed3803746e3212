#!/usr/bin/python3
"""Golden-mesh tests: run small pipelines on generated bodies and compare
their outputs with the files in testdata/golden/ within stated tolerances.

  scripts/golden.py --bin build/bin            compare (exit 1 on any difference)
  scripts/golden.py --bin build/bin --kernels haswell,skylakex,sandybridge-nofma
                                               the same under several CPU kernels
  scripts/golden.py --bin build/bin --update   rewrite the goldens, showing what changed

Meshes are compared by scripts/meshdiff.py (same topology: per-vertex
distance; otherwise Hausdorff), with tolerances relative to the bounding-box
diagonal; report figures by relative difference. Tolerances are loose enough
for a different --threads count (CHOLMOD and OpenBLAS may sum in another
order) and tight enough to catch any change of method.

With --kernels, each case runs once per emulated CPU: OpenBLAS is made to
pick another core type's kernels (OPENBLAS_CORETYPE) and, for a CPU without
FMA, glibc's libm its non-FMA code paths (GLIBC_TUNABLES). The pipeline
does its arithmetic with the same bits on every CPU (README.md,
"Reproducibility"), so every run must match the goldens within the
tolerances and every output file (timings aside; reports with the output
folder's path made relative) must be identical across the runs, bit for bit.
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshdiff  # noqa: E402

GOLDEN = os.path.join(ROOT, "testdata", "golden")

# Each case: a customer folder run through pipelines/fit.mk, the meshes to
# compare (path under OUT, relative tolerance), and report figures (JSON
# file under OUT, path of keys, relative tolerance).
CASES = {
    "small-shirt": {
        "customer": os.path.join(ROOT, "testdata", "customers", "small-shirt"),
        # (path, max, rms), fractions of the bounding-box diagonal. The cloth
        # run amplifies rounding differences (another --threads count moves
        # the rest shape by up to ~3 mm, 0.3 mm RMS, on a 1 m garment), and the
        # pattern's automatic cuts are discrete choices that may shift.
        "meshes": [
            ("garment/garment.ply", 1e-6, 1e-7),
            ("fit/rest.ply", 5e-3, 1e-3),
            ("fit/draped_01_tpose.ply", 5e-3, 1e-3),
            ("pattern/pieces_flat.ply", 5e-3, 1e-3),
        ],
        "figures": [
            ("body/report.json", ["max_girth_error_m"], None, 5e-4),
            ("garment/report.json", ["quality", "region_area"], 1e-6, None),
            ("garment/report.json", ["quality", "fraction_min_angle_over_20_deg"], 1e-9, None),
            ("fit/report.json", ["key_poses", 1, "max_stretch"], 2e-3, None),
            ("fit/report.json", ["key_poses", 1, "p99_stretch"], 2e-3, None),
            ("fit/report.json", ["key_poses", 1, "rest_area_growth"], 2e-3, None),
            ("pattern/report.json", ["summary", "pieces"], 0, None),
            ("pattern/report.json", ["summary", "area_2d"], 1e-3, None),
            ("pattern/report.json", ["summary", "total_seam_length"], 1e-2, None),
        ],
    },
}


# Emulated CPUs: the environment that makes OpenBLAS and libm take the code
# paths of another machine. Sandy Bridge has AVX but neither AVX2 nor FMA, so
# its glibc takes the non-FMA paths of exp, log, atan2, sin, cos and pow.
KERNELS = {
    "haswell": {"OPENBLAS_CORETYPE": "Haswell"},
    "skylakex": {"OPENBLAS_CORETYPE": "SkylakeX"},
    "zen": {"OPENBLAS_CORETYPE": "Zen"},
    "sandybridge-nofma": {"OPENBLAS_CORETYPE": "Sandybridge", "GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"},
}


def run_case(name, case, bin_dir, out, threads, env=None):
    r = subprocess.run(["make", "--no-print-directory", "-f", os.path.join(ROOT, "pipelines", "fit.mk"),
                        f"CUSTOMER={case['customer']}", f"OUT={out}", f"BIN={bin_dir}", f"THREADS={threads}"],
                       # The DXF's Creation Date comes from SOURCE_DATE_EPOCH where set, else
                       # from the rest shape's file date: fixed here, so that runs either side
                       # of midnight still write identical files.
                       cwd=ROOT, capture_output=True, text=True,
                       env={**os.environ, "SOURCE_DATE_EPOCH": "1764547200", **(env or {})})
    if r.returncode != 0:
        raise SystemExit(f"golden: {name}: the pipeline failed:\n{r.stdout}{r.stderr}")


def dig(j, keys):
    for k in keys:
        j = j[k]
    return j


def figure_file(name):
    return os.path.join(GOLDEN, name, "figures.json")


def collect_figures(case, out):
    figs = {}
    for path, keys, _, _ in case["figures"]:
        with open(os.path.join(out, path)) as f:
            figs[f"{path}:{'/'.join(map(str, keys))}"] = dig(json.load(f), keys)
    return figs


def compare_case(name, case, out, label=None):
    """Failures of the outputs in `out` against the goldens of case `name`;
    lines are printed and failures named with `label` (default: the name)."""
    failures = []
    golden_name, name = name, label or name
    for path, tol, rms_tol in case["meshes"]:
        golden = os.path.join(GOLDEN, golden_name, path.replace("/", "__"))
        if not os.path.isfile(golden):
            failures.append(f"{name}: no golden file for {path} (run make update-golden)")
            continue
        r = meshdiff.compare(golden, os.path.join(out, path), tol, rms_tol, True)
        line = meshdiff.summary(r)
        print(f"golden: {name}: {path}: {line}")
        if not r["equal"]:
            failures.append(f"{name}: {path} differs: {line}")
    with open(figure_file(golden_name)) as f:
        expected = json.load(f)
    got = collect_figures(case, out)
    for path, keys, rel, absolute in case["figures"]:
        key = f"{path}:{'/'.join(map(str, keys))}"
        e, g = expected.get(key), got[key]
        ok = e is not None and (abs(g - e) <= (rel * abs(e) if rel is not None else absolute))
        print(f"golden: {name}: {key}: {g} (golden {e}) {'ok' if ok else 'DIFFERENT'}")
        if not ok:
            failures.append(f"{name}: {key} is {g}, golden {e}")
    return failures


def run_outputs(out):
    """Every output file of a run (timings aside), as {path: content}: JSON
    parsed, with the output folder's path made relative and the hashes of
    files left out (poses.json, hashed into garment.json, names its folder);
    any other file as its bytes."""
    found = {}

    def normalize(value):
        if isinstance(value, dict):
            return {k: normalize(v) for k, v in value.items() if "sha256" not in k}
        if isinstance(value, list):
            return [normalize(v) for v in value]
        if isinstance(value, str):
            return value.replace(out, "<OUT>")
        return value

    for folder, _, files in sorted(os.walk(out)):
        for f in sorted(files):
            path = os.path.join(folder, f)
            rel = os.path.relpath(path, out)
            if f in ("timing.json", "timing.js"):
                continue
            if f.endswith(".json"):
                with open(path) as fh:
                    found[rel] = json.dumps(normalize(json.load(fh)), sort_keys=True)
            else:
                with open(path, "rb") as fh:
                    found[rel] = hashlib.sha256(fh.read().replace(out.encode(), b"<OUT>")).hexdigest()
    return found


def compare_outputs(reference_name, reference, name, got):
    """The files that differ between two runs' outputs (run_outputs)."""
    return [f"{path} ({reference_name} against {name})" for path in sorted(set(reference) | set(got))
            if reference.get(path) != got.get(path)]


def update_case(name, case, out):
    folder = os.path.join(GOLDEN, name)
    os.makedirs(folder, exist_ok=True)
    for path, tol, rms_tol in case["meshes"]:
        golden = os.path.join(folder, path.replace("/", "__"))
        if os.path.isfile(golden):
            r = meshdiff.compare(golden, os.path.join(out, path), tol, rms_tol, True)
            print(f"golden: {name}: {path}: {meshdiff.summary(r)}")
        else:
            print(f"golden: {name}: {path}: new")
        shutil.copyfile(os.path.join(out, path), golden)
    figs = collect_figures(case, out)
    if os.path.isfile(figure_file(name)):
        with open(figure_file(name)) as f:
            old = json.load(f)
        for k, v in figs.items():
            if old.get(k) != v:
                print(f"golden: {name}: {k}: {old.get(k)} -> {v}")
    with open(figure_file(name), "w") as f:
        json.dump(figs, f, indent=2, sort_keys=True)
        f.write("\n")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--bin", required=True, help="folder with the built stages")
    p.add_argument("--update", action="store_true", help="rewrite the golden files")
    p.add_argument("--threads", type=int, default=1, help="--threads for every stage (default 1)")
    p.add_argument("--case", action="append", help="run only this case (repeatable)")
    p.add_argument("--kernels", default="",
                   help="comma-separated emulated CPUs to run each case under (" + ", ".join(KERNELS) +
                        "; default: this machine's own)")
    args = p.parse_args()
    kernels = [k for k in args.kernels.split(",") if k]
    for k in kernels:
        if k not in KERNELS:
            p.error(f"unknown kernel '{k}' (known: {', '.join(KERNELS)})")
    if args.update and kernels:
        p.error("--update writes the goldens from this machine's own kernels; leave out --kernels")
    failures = []
    for name, case in CASES.items():
        if args.case and name not in args.case:
            continue
        reference = None
        for kernel in kernels or [None]:
            label = f"{name} [{kernel}]" if kernel else name
            out = tempfile.mkdtemp(prefix=f"gp_golden_{name}_")
            try:
                run_case(label, case, os.path.abspath(args.bin), out, args.threads, KERNELS.get(kernel))
                if args.update:
                    update_case(name, case, out)
                    continue
                failures += compare_case(name, case, out, label)
                if kernel:
                    got = run_outputs(out)
                    if reference is None:
                        reference = (kernel, got)
                        print(f"golden: {label}: {len(got)} output files")
                    else:
                        different = compare_outputs(reference[0], reference[1], kernel, got)
                        print(f"golden: {label}: output files "
                              f"{'identical' if not different else f'DIFFERENT in {len(different)}'} "
                              f"to those under {reference[0]}")
                        failures += [f"{name}: output differs: {d}" for d in different]
            finally:
                shutil.rmtree(out, ignore_errors=True)
    if failures:
        print("golden: FAILED:\n  " + "\n  ".join(failures))
        return 1
    print("golden: " + ("updated" if args.update else "all outputs match their goldens"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
