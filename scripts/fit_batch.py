#!/usr/bin/python3
"""Many customers' fits as one Slurm job array, and the batch's summary.

  scripts/fit_batch.py submit --batch DIR --bin BIN [--wait] CUSTOMER...
      writes DIR/manifest.json (one entry per customer folder), submits one
      `sbatch --array` job whose task i runs `make -f pipelines/fit.mk fit`
      for customer i (pipelines/slurm/fit-array.sbatch), and a summary job
      that starts when every task has ended, whatever its state
      (`--dependency=afterany`). With --wait it returns when the summary is
      written, with the summary's exit code.
  scripts/fit_batch.py task --batch DIR --index I
      one array task (the job script calls it): runs the customer's fit,
      passes make's output through, and writes DIR/tasks/I.json: the stages
      it ran, the failing stage, its exit code and its error line.
  scripts/fit_batch.py summary --batch DIR
      DIR/summary.json and DIR/summary.html: one row per customer with its
      state, failing stage and exit code, Slurm's state, and the fit and
      pattern figures read from the customer's own report.json files; exit 0
      only if every customer's fit succeeded.

Reruns cost nothing: each task runs make, which reruns only the stages whose
inputs, flags or binaries changed, and a failed stage again (a stage's
report.json is its target). A customer's failure never blocks the others:
every task runs on its own and the summary waits for all of them.

Slurm's own record of each task comes from `sacct` where the cluster keeps
accounting (slurmdbd); without it (`AccountingStorageType=accounting_storage/none`,
where sacct answers "Slurm accounting storage is disabled") from `scontrol
show job`, which the controller answers for MinJobAge seconds after a job
ends, and then from the job completion log of `JobCompType=jobcomp/filetxt`,
read directly: Slurm 22.05's `sacct --completion` reads that log but not its
array fields ("Unknown type ArrayJobId"), so it cannot tell the tasks apart.
The summary names the sources it used.
"""
import argparse
import datetime
import html
import json
import os
import re
import shlex
import socket
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
FIT_MK = os.path.join(ROOT, "pipelines", "fit.mk")
ARRAY_SCRIPT = os.path.join(ROOT, "pipelines", "slurm", "fit-array.sbatch")
SUMMARY_SCRIPT = os.path.join(ROOT, "pipelines", "slurm", "fit-summary.sbatch")

MANIFEST_SCHEMA = "fit-batch-manifest/1"
TASK_SCHEMA = "fit-batch-task/1"
SUMMARY_SCHEMA = "fit-batch-summary/1"

# pipelines/fit.mk writes one folder per stage under OUT, its report.json the
# stage's target: a failing target names its stage.
STAGE_OF_FOLDER = {
    "body": "make-avatar",
    "poses": "register-check",
    "garment": "make-garment",
    "extended": "extend-boundary",
    "fit": "simulate-adapt",
    "fit-noadapt": "simulate-adapt",
    "pattern": "export-rest",
    "report": "fit-report",
}
# The exit codes every stage shares (README.md, "Conventions shared by every stage").
CATEGORY = {1: "internal", 2: "usage", 3: "input", 4: "spec", 5: "geometry", 6: "numerical", 7: "output",
            8: "check"}

STAGE_LINE = re.compile(r"^fit: ([a-z-]+)$")
# GNU make: "make: *** [pipelines/fit.mk:97: OUT/garment/report.json] Error 4"
# (or "make[1]: *** [OUT/garment/report.json] Error 4" without the line).
MAKE_ERROR = re.compile(r"^make(?:\[\d+\])?: \*\*\* \[(?:.*?:\d+: )?(.+?)\] Error (\d+)")
TOOL_ERROR = re.compile(r"^([a-z-]+): error\[([a-z]+)\]: ")


class BatchError(Exception):
    """A problem with the batch itself (usage, files, Slurm refusing a job): exit 2."""


def read_json(path):
    with open(path) as f:
        return json.load(f)


def write_json(path, data):
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)


def now_utc():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


# --- manifest -------------------------------------------------------------------

def customer_outputs(customers, out_root):
    """OUT of each customer: CUSTOMER/out (as `make fit` and the local
    fit-all), or OUT_ROOT/<folder name>, numbered where two folders share a name."""
    if out_root is None:
        return [os.path.join(c, "out") for c in customers]
    names = [os.path.basename(c) for c in customers]
    outs = []
    for i, name in enumerate(names):
        outs.append(os.path.join(out_root, name if names.count(name) == 1 else f"{name}-{i}"))
    return outs


def make_manifest(batch, bin_dir, customers, out_root, fit_vars):
    customers = [os.path.abspath(c.rstrip("/")) for c in customers]
    if not customers:
        raise BatchError("no customers (CUSTOMERS=\"dir dir ...\")")
    for c in customers:
        if not os.path.isdir(c):
            raise BatchError(f"customer folder {c} does not exist")
    if len(set(customers)) != len(customers):
        raise BatchError("a customer folder is listed twice")
    outs = customer_outputs(customers, os.path.abspath(out_root) if out_root else None)
    return {
        "schema": MANIFEST_SCHEMA,
        "root": ROOT,
        "bin": os.path.abspath(bin_dir),
        "fit_vars": list(fit_vars),
        "customers": [{"index": i, "name": os.path.basename(c), "customer": c, "out": o}
                      for i, (c, o) in enumerate(zip(customers, outs))],
    }


def load_manifest(batch):
    path = os.path.join(batch, "manifest.json")
    try:
        m = read_json(path)
    except (OSError, ValueError) as e:
        raise BatchError(f"cannot read the batch manifest {path}: {e}")
    if m.get("schema") != MANIFEST_SCHEMA:
        raise BatchError(f"{path}: /schema: expected {MANIFEST_SCHEMA}, got {m.get('schema')!r}")
    return m


# --- submit ---------------------------------------------------------------------

def run(cmd, check=True):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if check and r.returncode != 0:
        raise BatchError(f"{shlex.join(cmd)} failed ({r.returncode}): {r.stderr.strip() or r.stdout.strip()}")
    return r


def max_array_size():
    r = run(["scontrol", "show", "config"], check=False)
    m = re.search(r"^MaxArraySize\s*=\s*(\d+)", r.stdout, flags=re.M)
    return int(m.group(1)) if m else 1001


def jobs_still_queued(batch):
    path = os.path.join(batch, "jobs.json")
    if not os.path.isfile(path):
        return []
    jobs = read_json(path)
    ids = [str(j) for j in (jobs.get("array_job_id"), jobs.get("summary_job_id")) if j]
    if not ids:
        return []
    r = run(["squeue", "--noheader", "--format=%i", "--jobs", ",".join(ids)], check=False)
    return [line.strip() for line in r.stdout.splitlines() if line.strip()]


def submit(args):
    batch = os.path.abspath(args.batch)
    os.makedirs(os.path.join(batch, "logs"), exist_ok=True)
    os.makedirs(os.path.join(batch, "tasks"), exist_ok=True)
    queued = jobs_still_queued(batch)
    if queued:
        raise BatchError(f"the batch's previous jobs are still queued or running ({', '.join(queued)}); "
                         f"wait for them or scancel them before resubmitting")
    manifest = make_manifest(batch, args.bin, args.customers, args.out_root, args.fit_var or [])
    n = len(manifest["customers"])
    limit = max_array_size()
    if n > limit:
        raise BatchError(f"{n} customers, but the cluster's MaxArraySize is {limit}: split the batch "
                         f"or raise MaxArraySize in slurm.conf")
    write_json(os.path.join(batch, "manifest.json"), manifest)
    # A previous submission's summary must not pass for this one's.
    for f in ("summary.json", "summary.html"):
        if os.path.exists(os.path.join(batch, f)):
            os.remove(os.path.join(batch, f))

    array = f"0-{n - 1}" + (f"%{args.max_running}" if args.max_running else "")
    name = f"fit-{os.path.basename(batch)}"
    extra = shlex.split(args.sbatch_flags or "")
    # The job scripts are copied to the node's spool, so they are given the
    # repository and the batch folder (both on shared storage) as arguments.
    r = run(["sbatch", "--parsable", f"--array={array}", f"--job-name={name}", f"--chdir={ROOT}",
             f"--output={batch}/logs/fit-%A_%a.out", *extra, ARRAY_SCRIPT, ROOT, batch])
    array_id = r.stdout.strip().split(";")[0]
    summary_cmd = ["sbatch", "--parsable", f"--dependency=afterany:{array_id}", "--kill-on-invalid-dep=yes",
                   f"--job-name={name}-summary", f"--chdir={ROOT}", f"--output={batch}/logs/summary-%j.out",
                   *extra]
    jobs = {"schema": "fit-batch-jobs/1", "array_job_id": array_id, "summary_job_id": None,
            "submitted": now_utc(), "customers": n}
    write_json(os.path.join(batch, "jobs.json"), jobs)
    if not args.wait:
        r = run(summary_cmd + [SUMMARY_SCRIPT, ROOT, batch, array_id])
        jobs["summary_job_id"] = r.stdout.strip().split(";")[0]
        write_json(os.path.join(batch, "jobs.json"), jobs)
        print(f"fit-all: {n} customers in array job {array_id}, summary job {jobs['summary_job_id']}; "
              f"the summary will be {batch}/summary.html (squeue --jobs {array_id},{jobs['summary_job_id']})")
        return 0
    print(f"fit-all: {n} customers in array job {array_id}; waiting for the summary job", flush=True)
    # sbatch --wait returns when the summary job ends, with its exit code; it
    # prints the job id first, so the id is recorded before the wait.
    p = subprocess.Popen(summary_cmd + ["--wait", SUMMARY_SCRIPT, ROOT, batch, array_id],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = p.stdout.readline().strip()
    if first:
        jobs["summary_job_id"] = first.split(";")[0]
        write_json(os.path.join(batch, "jobs.json"), jobs)
    out, err = p.communicate()
    status = p.returncode
    if not os.path.isfile(os.path.join(batch, "summary.json")) or status not in (0, 1):
        sys.stderr.write(err)
        raise BatchError(f"the summary job {jobs['summary_job_id']} ended with {status} "
                         f"(log: {batch}/logs/summary-{jobs['summary_job_id']}.out)")
    print_summary(read_json(os.path.join(batch, "summary.json")), batch)
    return status


# --- task -----------------------------------------------------------------------

def failing_stage(out, lines, make_status):
    """(stage, exit code, error line) of a failed `make fit`, from make's own
    error line: the target that failed is a stage's report.json, or `fit`
    itself when a check's verdict is "fail" (exit 8, outputs complete)."""
    target, code = None, make_status
    for line in lines:
        m = MAKE_ERROR.match(line)
        if m:
            target, code = m.group(1), int(m.group(2))
    error = next((line for line in lines if TOOL_ERROR.match(line) or line.startswith("fit: error[")), None)
    started = [m.group(1) for m in map(STAGE_LINE.match, lines) if m]
    if target is None:
        # No error line from make: it was killed (the stage's exit code is the signal's).
        return (started[-1] if started else None), code, error
    if target == "fit":
        stage = "simulate-adapt"
        pattern = os.path.join(out, "pattern", "report.json")
        fit_report = os.path.join(out, "fit", "report.json")
        if not verdict_failed(fit_report) and verdict_failed(pattern):
            stage = "export-rest"
        return stage, code, error
    folder = os.path.basename(os.path.dirname(target))
    return STAGE_OF_FOLDER.get(folder, started[-1] if started else None), code, error


def verdict_failed(path):
    try:
        with open(path) as f:
            return re.search(r'"verdict": *"fail"', f.read()) is not None
    except OSError:
        return False


def task(args):
    batch = os.path.abspath(args.batch)
    manifest = load_manifest(batch)
    index = args.index
    if index is None:
        index = int(os.environ["SLURM_ARRAY_TASK_ID"])
    entry = manifest["customers"][index]
    threads = os.environ.get("SLURM_CPUS_PER_TASK", "1")
    cmd = ["make", "--no-print-directory", "-f", os.path.join(manifest["root"], "pipelines", "fit.mk"), "fit",
           f"CUSTOMER={entry['customer']}", f"OUT={entry['out']}", f"BIN={manifest['bin']}",
           f"THREADS={threads}", *manifest["fit_vars"]]
    started_at = now_utc()
    t0 = time.monotonic()
    print(f"fit-task: {entry['name']} ({entry['customer']}) -> {entry['out']}", flush=True)
    print(f"fit-task: {shlex.join(cmd)}", flush=True)
    lines = []
    # make's output passes through to the task's Slurm output file as it comes.
    p = subprocess.Popen(cmd, cwd=manifest["root"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for line in p.stdout:
        sys.stdout.write(line)
        sys.stdout.flush()
        lines.append(line.rstrip("\n"))
    status = p.wait()
    stages = [m.group(1) for m in map(STAGE_LINE.match, lines) if m]
    record = {
        "schema": TASK_SCHEMA,
        "array_job_id": os.environ.get("SLURM_ARRAY_JOB_ID"),
        "task_id": index,
        "job_id": os.environ.get("SLURM_JOB_ID"),
        "customer": entry["customer"],
        "out": entry["out"],
        "host": socket.gethostname(),
        "threads": int(threads),
        "started": started_at,
        "elapsed_s": round(time.monotonic() - t0, 3),
        "stages_run": stages,
        "make_exit": status,
    }
    if status == 0:
        record.update(state="completed", failing_stage=None, exit_code=0, error=None)
    else:
        stage, code, error = failing_stage(entry["out"], lines, status)
        record.update(state="failed", failing_stage=stage, exit_code=code, error=error)
    write_json(os.path.join(batch, "tasks", f"{index}.json"), record)
    # Slurm records the failing stage's own exit code (4: spec, 8: check, ...).
    return record["exit_code"] if 0 <= record["exit_code"] < 256 else 1


# --- Slurm's record of the tasks -------------------------------------------------

def parse_key_values(line):
    """`Key=Value Key=Value ...` (scontrol -o, jobcomp/filetxt) into a dict;
    values without spaces, as both print the fields read here."""
    return dict(f.split("=", 1) for f in line.split() if "=" in f)


def exit_code_of(text):
    """Slurm's "code:signal" as one number: the code, or 128 + the signal."""
    try:
        code, sig = (int(x) for x in text.split(":"))
    except ValueError:
        return None
    return 128 + sig if sig else code


# Slurm's commands retry for a minute when they cannot reach the controller;
# the summary gives each query this long and goes on without its answer.
QUERY_TIMEOUT_S = 30


_silent = set()


def query(cmd):
    """A Slurm command's result, or None where it is missing or does not
    answer (and then it is not asked again)."""
    if cmd[0] in _silent:
        return None
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=QUERY_TIMEOUT_S)
    except (OSError, subprocess.TimeoutExpired):
        _silent.add(cmd[0])
        return None


def states_from_sacct(array_id):
    r = query(["sacct", "--jobs", array_id, "--noheader", "--parsable2",
                        "--format=JobID,State,ExitCode,Elapsed,NodeList"])
    if r is None or r.returncode != 0:
        return None
    states = {}
    for line in r.stdout.splitlines():
        fields = line.split("|")
        if len(fields) < 5:
            continue
        m = re.fullmatch(rf"{re.escape(array_id)}_(\d+)", fields[0])
        if not m:
            continue  # job steps (.batch, .extern) and pending ranges
        states[int(m.group(1))] = {"state": fields[1].split()[0], "exit_code": exit_code_of(fields[2]),
                                   "elapsed": fields[3], "nodes": fields[4]}
    return states


def states_from_records(lines, array_id, state_key):
    states = {}
    for line in lines:
        kv = parse_key_values(line)
        if kv.get("ArrayJobId") != array_id or not kv.get("ArrayTaskId", "").isdigit():
            continue
        states[int(kv["ArrayTaskId"])] = {"state": kv.get(state_key), "exit_code": exit_code_of(kv.get("ExitCode", "")),
                                          "elapsed": kv.get("RunTime"), "nodes": kv.get("NodeList")}
    return states


def states_from_scontrol(array_id):
    r = query(["scontrol", "--oneliner", "show", "job", array_id])
    if r is None or r.returncode != 0:
        return None
    return states_from_records(r.stdout.splitlines(), array_id, "JobState") or None


def states_from_jobcomp(array_id):
    r = query(["scontrol", "show", "config"])
    if r is None:
        return None
    kind = re.search(r"^JobCompType\s*=\s*(\S+)", r.stdout, flags=re.M)
    loc = re.search(r"^JobCompLoc\s*=\s*(\S+)", r.stdout, flags=re.M)
    if not kind or kind.group(1) != "jobcomp/filetxt" or not loc or not os.path.isfile(loc.group(1)):
        return None
    with open(loc.group(1)) as f:
        return states_from_records(f.read().splitlines(), array_id, "JobState") or None


def slurm_states(array_id, task_ids):
    """{task id: {state, exit_code, elapsed, nodes}} and the sources they came
    from: each task from the first source that knows it."""
    states, used = {}, []
    if not array_id:
        return states, used
    for source, fetch in (("sacct", states_from_sacct), ("scontrol", states_from_scontrol),
                          ("jobcomp", states_from_jobcomp)):
        found = fetch(array_id) or {}
        new = {i: v for i, v in found.items() if i in task_ids and i not in states}
        if new:
            states.update(new)
            used.append(source)
        if len(states) == len(task_ids):
            break
    return states, used


# --- summary --------------------------------------------------------------------

def pick(data, *keys):
    for k in keys:
        if isinstance(data, dict) and k in data:
            data = data[k]
        elif isinstance(data, list) and isinstance(k, int) and -len(data) <= k < len(data):
            data = data[k]
        else:
            return None
    return data


def worst(poses, key):
    values = [p.get(key) for p in poses or [] if isinstance(p.get(key), (int, float))]
    return max(values) if values else None


def fit_figures(out):
    """The fit's and the pattern's figures, as the customer's own reports give them."""
    figures = {}
    fit_path = os.path.join(out, "fit", "report.json")
    if os.path.isfile(fit_path):
        fit = read_json(fit_path)
        verified = pick(fit, "verification", "key_poses")
        figures["fit"] = {
            "verdict": pick(fit, "verification", "verdict"),
            "max_stretch": worst(verified, "max_stretch"),
            "p99_stretch": worst(verified, "p99_stretch"),
            "area_fraction_above_limit": worst(verified, "area_fraction_above_limit"),
            "rest_area_growth": pick(fit, "run", "rest_area_growth"),
            "steps": pick(fit, "run", "steps"),
            "garment_vertices": pick(fit, "counts", "garment_vertices"),
        }
    pattern_path = os.path.join(out, "pattern", "report.json")
    if os.path.isfile(pattern_path):
        pattern = read_json(pattern_path)
        figures["pattern"] = {
            "pieces": pick(pattern, "summary", "pieces"),
            "total_seam_length_m": pick(pattern, "summary", "total_seam_length"),
            "area_2d_m2": pick(pattern, "summary", "area_2d"),
            # "not checked" where the fit ran with NO_SEW_CHECK=1.
            "sewn_fit_verdict": (pick(pattern, "sewn_fit", "verdict") if pick(pattern, "sewn_fit", "checked")
                                 else "not checked"),
        }
    return figures


def customer_row(entry, record, slurm, batch, log_lines):
    row = {"index": entry["index"], "name": entry["name"], "customer": entry["customer"], "out": entry["out"]}
    if record is not None:
        row.update(state=record["state"], failing_stage=record["failing_stage"], exit_code=record["exit_code"],
                   error=record["error"], stages_run=record["stages_run"], elapsed_s=record["elapsed_s"],
                   host=record["host"])
    elif slurm and slurm.get("state") not in (None, "PENDING", "RUNNING"):
        # The task ended without writing its record: Slurm ended it (time or
        # memory limit, cancelled, node failure); its last stage from its log.
        started = [m.group(1) for m in map(STAGE_LINE.match, log_lines) if m]
        row.update(state=slurm["state"].lower(), failing_stage=started[-1] if started else None,
                   exit_code=slurm.get("exit_code"), error=None, stages_run=started, elapsed_s=None, host=None)
    else:
        row.update(state="missing", failing_stage=None, exit_code=None, error=None, stages_run=None,
                   elapsed_s=None, host=None)
    row["category"] = CATEGORY.get(row["exit_code"]) if row["exit_code"] else None
    row["slurm"] = slurm
    # Figures only where the pipeline ran to its end (a check's fail, exit 8,
    # still writes every output): after an earlier failure the later reports
    # would be a previous run's.
    complete = row["state"] == "completed" or (row["state"] == "failed" and row["exit_code"] == 8
                                               and row["failing_stage"] in ("simulate-adapt", "export-rest"))
    row["figures"] = fit_figures(entry["out"]) if complete else {}
    index = os.path.join(entry["out"], "report", "index.html")
    row["report"] = os.path.relpath(index, batch) if complete and os.path.isfile(index) else None
    return row


def summarize(batch, array_id=None):
    manifest = load_manifest(batch)
    if array_id is None:
        array_id = read_json(os.path.join(batch, "jobs.json")).get("array_job_id")
    states, sources = slurm_states(array_id, {e["index"] for e in manifest["customers"]})
    rows = []
    for entry in manifest["customers"]:
        i = entry["index"]
        record = None
        path = os.path.join(batch, "tasks", f"{i}.json")
        if os.path.isfile(path):
            r = read_json(path)
            if r.get("schema") == TASK_SCHEMA and (array_id is None or r.get("array_job_id") == array_id):
                record = r  # a previous submission's record does not count
        log = os.path.join(batch, "logs", f"fit-{array_id}_{i}.out")
        log_lines = open(log).read().splitlines() if os.path.isfile(log) else []
        rows.append(customer_row(entry, record, states.get(i), batch, log_lines))
    counts = {}
    for row in rows:
        counts[row["state"]] = counts.get(row["state"], 0) + 1
    return {
        "schema": SUMMARY_SCHEMA,
        "batch": batch,
        "array_job_id": array_id,
        "slurm_state_sources": sources,
        "written": now_utc(),
        "customers": len(rows),
        "counts": dict(sorted(counts.items())),
        "all_succeeded": all(r["state"] == "completed" for r in rows),
        "rows": rows,
    }


def fmt(value, digits=3):
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.{digits}f}"
    return str(value)


def summary_html(summary):
    e = html.escape
    head = ["#", "customer", "state", "failing stage", "exit", "Slurm", "verdict", "max stretch", "p99 stretch",
            "rest area", "pieces", "seams (m)", "sewn fit", "report", "error"]
    rows = []
    for r in summary["rows"]:
        fit, pattern = r["figures"].get("fit", {}), r["figures"].get("pattern", {})
        slurm = r["slurm"] or {}
        exit_code = "" if r["exit_code"] is None else f"{r['exit_code']}" + (f" ({r['category']})" if r["category"] else "")
        cells = [str(r["index"]), e(r["name"]), e(r["state"]), e(r["failing_stage"] or ""), e(exit_code),
                 e(f"{slurm.get('state') or ''} {slurm.get('exit_code') if slurm.get('exit_code') is not None else ''}".strip()),
                 e(fit.get("verdict") or ""), fmt(fit.get("max_stretch")), fmt(fit.get("p99_stretch")),
                 fmt(fit.get("rest_area_growth")), fmt(pattern.get("pieces")),
                 fmt(pattern.get("total_seam_length_m"), 2), e(pattern.get("sewn_fit_verdict") or ""),
                 f'<a href="{e(r["report"])}">fit report</a>' if r["report"] else "",
                 f'<code>{e(r["error"])}</code>' if r.get("error") else ""]
        rows.append(f'<tr class="{e(r["state"])}">' + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    counts = ", ".join(f"{v} {k}" for k, v in summary["counts"].items())
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Fit batch {e(os.path.basename(summary['batch']))}</title>
<style>
body {{ font: 14px sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }}
td, th {{ border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }}
tr.completed td:nth-child(3) {{ color: #186a18; }}
tr:not(.completed) td:nth-child(3) {{ color: #b00; font-weight: bold; }}
</style></head><body>
<h1>Fit batch {e(os.path.basename(summary['batch']))}</h1>
<p>{summary['customers']} customers: {e(counts)}. Slurm array job {e(str(summary['array_job_id']))}, states from
{e(', '.join(summary['slurm_state_sources']) or 'nowhere')}. Stretch figures are the verification's worst key pose; rest area is the
rest shape's area over the design's.</p>
<table><thead><tr>{''.join(f'<th>{h}</th>' for h in head)}</tr></thead>
<tbody>
{chr(10).join(rows)}
</tbody></table>
</body></html>
"""


def print_summary(summary, batch):
    for r in summary["rows"]:
        if r["state"] == "completed":
            what = "completed"
        elif r["state"] == "missing":
            what = "missing: its task left no record and Slurm knows no state of it"
        else:
            what = f"{r['state']} at {r['failing_stage'] or 'an unknown stage'} (exit {r['exit_code']})"
        print(f"fit-all: {r['name']}: {what}")
    print(f"fit-all: summary: {batch}/summary.html")


def summary(args):
    batch = os.path.abspath(args.batch)
    s = summarize(batch, args.job)
    write_json(os.path.join(batch, "summary.json"), s)
    tmp = os.path.join(batch, f"summary.html.tmp{os.getpid()}")
    with open(tmp, "w") as f:
        f.write(summary_html(s))
    os.replace(tmp, os.path.join(batch, "summary.html"))
    print_summary(s, batch)
    return 0 if s["all_succeeded"] else 1


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("submit", help="write the manifest and submit the array and its summary job")
    s.add_argument("--batch", required=True, help="batch folder on shared storage (manifest, logs, summary)")
    s.add_argument("--bin", required=True, help="the stages' folder (build/bin), on shared storage")
    s.add_argument("--out-root", help="fit outputs in OUT_ROOT/<customer name> (default: CUSTOMER/out)")
    s.add_argument("--max-running", type=int, help="at most this many tasks at once (sbatch --array=...%%N)")
    s.add_argument("--sbatch-flags", help="more sbatch options for both jobs, e.g. '--partition=cpu --account=x'")
    s.add_argument("--fit-var", action="append", help="a variable for pipelines/fit.mk, e.g. NO_ADAPT=1 (repeatable)")
    s.add_argument("--wait", action="store_true", help="return when the summary is written, with its exit code")
    s.add_argument("customers", nargs="*", help="customer folders")
    t = sub.add_parser("task", help="run one array task (the job script calls it)")
    t.add_argument("--batch", required=True)
    t.add_argument("--index", type=int, help="the customer's index (default: SLURM_ARRAY_TASK_ID)")
    m = sub.add_parser("summary", help="write summary.json and summary.html; exit 0 only if every fit succeeded")
    m.add_argument("--batch", required=True)
    m.add_argument("--job", help="the array job id (default: the batch's last submission, jobs.json)")
    args = p.parse_args(argv)
    try:
        return {"submit": submit, "task": task, "summary": summary}[args.command](args)
    except BatchError as e:
        print(f"fit-batch: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
