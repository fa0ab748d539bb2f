"""Reading the tools' outputs: frames.csv, summary.json, run.json, frame sidecars.

Plain values out (dicts, tuples in thesis.COMPONENTS order), so the
experiments and plots know the file formats only through this module.
"""

import csv
import json

from .thesis import COMPONENTS


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_frames(run_dir):
    rows = []
    with open(run_dir / "frames.csv", newline="") as f:
        for r in csv.DictReader(f):
            row = {"frame": int(r["frame"]), "region": r["region"], "status": r["status"],
                   "range_m": float(r["range_m"])}
            for k, v in r.items():
                if k == "truth_error_by_fraction":  # count/sum pairs (docs/analysis.md)
                    continue
                if k.startswith(("err_", "est_", "truth_", "ms_")) or k in ("sensed_points", "icp_rmse_m"):
                    row[k] = float(v) if v not in ("", None) else None
            rows.append(row)
    return rows


def ok_rows(rows):
    return [r for r in rows if r["status"] == "ok"]


def pairing_of(run_dir):
    """ICP pairing direction a run used, from its run.json."""
    return read_json(run_dir / "run.json").get("options", {}).get("icp", {}).get("correspondence", "?")


def group_stats(summary, model, group, kind):
    """summary.json models.<model>.<group>.<kind> as a tuple in COMPONENTS order (None if absent)."""
    g = summary["models"][model][group]
    values = g.get(kind)
    if values is None:
        return None
    return tuple(values[c] for c in COMPONENTS)


def group_counts(summary, model, group):
    g = summary["models"][model][group]
    return g["ok"], g["frames"]


def group_table(key_model, groups, kind):
    """{group: {label: tuple}} from {label: (summary, model)}: one statistic of several runs per group."""
    return {g: {label: group_stats(s, m, g, kind) for label, (s, m) in key_model.items()} for g in groups}


def group_table_counts(key_model, groups):
    """{group: {label: (ok, all) frames}} from {label: (summary, model)}."""
    return {g: {label: group_counts(s, m, g) for label, (s, m) in key_model.items()} for g in groups}


def sidecar(dataset, frame):
    return read_json(dataset / "frames" / f"{frame:06d}.json")


def summary_without_timing(path):
    s = read_json(path)
    s.pop("timing", None)
    return json.dumps(s, sort_keys=True, indent=1).encode()


def frames_csv_without_timing(path):
    """frames.csv with the ms_* columns (the last six) removed, as bytes."""
    out = []
    with open(path, newline="") as f:
        for line in f.read().splitlines():
            out.append(",".join(line.split(",")[:28]))
    return ("\n".join(out) + "\n").encode()
