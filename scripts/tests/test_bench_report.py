#!/usr/bin/python3
"""bench_report keeps the sections written into BENCHMARKS.md by hand when
make bench writes the file again."""
import os
import sys
import tempfile
import types

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bench_report  # noqa: E402

OLD = """# Benchmarks

Generated long ago.

## simulate-adapt: time per step

old generated rows

## The static solve by hand

| fit | CPU |
| --- | ---: |
| demo | 15.6 s |

### A subsection of it

more text

## Every measured run

| stage | case |

## Build time of the stages

5 min 29 s


"""


def check(condition, message):
    if not condition:
        print(f"FAIL: {message}")
        sys.exit(1)


def main():
    sections = bench_report.split_sections(OLD)
    check([h for h, _ in sections] == ["simulate-adapt: time per step", "The static solve by hand",
                                       "Every measured run", "Build time of the stages"],
          f"sections: {[h for h, _ in sections]}")
    kept = bench_report.carried_over(OLD, ["## simulate-adapt: time per step", "", "## Every measured run"])
    check(len(kept) == 2, f"two hand sections kept, got {len(kept)}")
    check(kept[0][0] == "## The static solve by hand" and "### A subsection of it" in kept[0]
          and "| demo | 15.6 s |" in kept[0], f"the first with its table and subsection: {kept[0]}")
    check(kept[1] == ["## Build time of the stages", "", "5 min 29 s"], f"the second, trimmed: {kept[1]}")

    # The whole writer: a run without results writes its generated sections
    # and keeps both hand sections, the generated ones replaced.
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "BENCHMARKS.md")
        with open(path, "w") as f:
            f.write(OLD)
        bench = types.SimpleNamespace(results={}, rows=[], notes=[])
        meta = {"date": "2026-12-02 00:00 UTC", "machine": "test", "load_before": "0", "load_after": "0",
                "total_s": 1.0, "processes": 0, "budget_s": 1.0, "quick": True, "repeats": 1,
                "plots_rel": "plots"}
        bench_report.write(path, bench, meta, [])
        with open(path) as f:
            new = f.read()
        check("old generated rows" not in new, "the generated section is written afresh")
        check(new.count("## The static solve by hand") == 1 and "| demo | 15.6 s |" in new,
              "the hand section on the static solve is kept once")
        check(new.count("## Build time of the stages") == 1 and "5 min 29 s" in new,
              "the hand section after the runs' table is kept once")
        check(new.index("## Build time of the stages") < new.index("## Every measured run"),
              "hand sections come before the table of runs")
        # Writing again changes nothing: nothing is carried twice.
        bench_report.write(path, bench, meta, [])
        with open(path) as f:
            again = f.read()
        check(again == new, "a second write gives the same file")
    print("bench_report: hand sections kept")


if __name__ == "__main__":
    main()
