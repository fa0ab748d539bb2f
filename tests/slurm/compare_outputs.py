#!/usr/bin/env python3
"""Compares the merged output of a Slurm job array with a single-process run's (tests/slurm/slurm_workflow_test.sh).

Usage: compare_outputs.py MERGED SINGLE SHARDS

Byte for byte, timings aside (docs/analysis.md, "Output folder of `run`"):
  frames.csv       without its ms_* columns (by header name)
  bop_results.csv  without its `time` column (by header name)
  summary.json     without its `timing` object; every other key and value as the file writes it (numbers
                   compared as their text, keys in the file's order)
  summary.md       without its section "## ICP execution time ..." (machine-dependent)
  run.json         the same, but `frames`: the merge writes "merged from SHARDS shards"
and the merged folder holds no other file than these and .aar-output. Exits 1 with every difference found.
"""
import json
import sys
from pathlib import Path


def drop_columns(path, drop):
    """The CSV's lines without the columns whose header name `drop` accepts (no quoted commas in these files)."""
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    keep = [i for i, name in enumerate(header) if not drop(name)]
    dropped = [name for name in header if drop(name)]
    rows = [",".join(line.split(",")[i] for i in keep) for line in lines]
    return rows, dropped


def json_text(path):
    """The JSON as (key, value) pairs in file order, numbers kept as their literal text."""
    return json.loads(path.read_text(), object_pairs_hook=list, parse_float=str, parse_int=str)


def without(pairs, key):
    return [(k, v) for k, v in pairs if k != key]


def markdown_without_timing(path):
    out, skipping = [], False
    for line in path.read_text().splitlines():
        if line.startswith("## "):
            skipping = line.startswith("## ICP execution time")
        if not skipping:
            out.append(line)
    return out


def main():
    merged, single, shards = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3])
    errors = []

    def same(what, a, b):
        if a != b:
            errors.append(f"{what}: the merged output differs from the single run's")
            for x, y in zip(a, b):
                if x != y:
                    errors.append(f"  first difference:\n    merged: {x}\n    single: {y}")
                    break
            else:
                errors.append(f"  merged has {len(a)} entries, single {len(b)}")
        return a == b

    names = sorted(p.name for p in merged.iterdir())
    expected = sorted([".aar-output", "bop_results.csv", "frames.csv", "run.json", "summary.json", "summary.md"])
    if names != expected:
        errors.append(f"merged folder holds {names}, expected {expected}")

    frames_m, dropped_m = drop_columns(merged / "frames.csv", lambda n: n.startswith("ms_"))
    frames_s, dropped_s = drop_columns(single / "frames.csv", lambda n: n.startswith("ms_"))
    if len(dropped_m) != 6 or dropped_m != dropped_s:
        errors.append(f"frames.csv timing columns: merged {dropped_m}, single {dropped_s} (expected six ms_*)")
    same("frames.csv without ms_*", frames_m, frames_s)

    bop_m, dropped_m = drop_columns(merged / "bop_results.csv", lambda n: n == "time")
    bop_s, _ = drop_columns(single / "bop_results.csv", lambda n: n == "time")
    if dropped_m != ["time"]:
        errors.append(f"bop_results.csv: no time column ({dropped_m})")
    same("bop_results.csv without time", bop_m, bop_s)

    summary_m, summary_s = json_text(merged / "summary.json"), json_text(single / "summary.json")
    if "timing" not in dict(summary_m) or "timing" not in dict(summary_s):
        errors.append("summary.json: no timing object")
    same("summary.json without timing", without(summary_m, "timing"), without(summary_s, "timing"))

    same("summary.md without the ICP execution time table", markdown_without_timing(merged / "summary.md"),
         markdown_without_timing(single / "summary.md"))

    run_m, run_s = json_text(merged / "run.json"), json_text(single / "run.json")
    if dict(run_m).get("frames") != f"merged from {shards} shards":
        errors.append(f"merged run.json: frames is {dict(run_m).get('frames')!r}, expected 'merged from {shards} shards'")
    same("run.json without frames", without(run_m, "frames"), without(run_s, "frames"))

    rows = len(frames_s) - 1
    ok = sum(1 for line in frames_s[1:] if line.split(",")[4] == "ok")
    if errors:
        print("\n".join(errors), file=sys.stderr)
        return 1
    print(f"merged == single (timings aside): frames.csv ({rows} frames, {ok} ok), bop_results.csv, summary.json, "
          "summary.md, run.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
