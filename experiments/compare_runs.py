#!/usr/bin/python3
"""Compare `aar-analyze run` folders per region, on the frames they share.

    experiments/compare_runs.py LABEL=RUN_DIR [LABEL=RUN_DIR ...] [--shard K/N]

Prints one Markdown table: per region (A, B, C) and run, frames measured /
analyzed, mean absolute error of x, y, z [m] and roll, pitch, yaw [deg] over
the measured frames (status ok), and, where frames.csv has the depth-truth
columns (datasets rendered with --depth), the sensed points off the receiver
and off the surface [% of the points] and the RMS disparity error of the
points on the receiver [px] (docs/analysis.md, "The cloud against depth
truth"), and, for datasets with the boom, the mean fraction of the receiver
the boom hides (receiver_occluded_fraction, docs/analysis.md, "The boom"). Only frames that every run analyzed are counted (and, with --shard,
only frames i with i % N == K), so runs over different subsets compare on the
same frames. Reads the runs with python/aar_stereo (NumPy).
"""

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
import aar_stereo  # noqa: E402

COMPONENTS = ("x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg")


def read(run_dir):
    return {r["frame"]: r for r in aar_stereo.open_run(run_dir)}


def fmt(value, digits):
    return "-" if value is None else f"{value:.{digits}f}"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", metavar="LABEL=RUN_DIR")
    parser.add_argument("--shard", metavar="K/N", help="only frames i with i %% N == K")
    args = parser.parse_args(argv)
    runs = []
    for item in args.runs:
        label, sep, path = item.partition("=")
        if not sep:
            parser.error(f"{item}: expected LABEL=RUN_DIR")
        runs.append((label, read(path)))
    common = set.intersection(*(set(frames) for _, frames in runs))
    if args.shard:
        k, n = (int(v) for v in args.shard.split("/"))
        common = {i for i in common if i % n == k}
    boom = any("receiver_occluded_fraction" in next(iter(frames.values()), {}) for _, frames in runs)
    print("| Region | Run | Measured | " + " | ".join(f"MAE {c}" for c in COMPONENTS)
          + " | Off receiver (%) | Off surface (%) | RMS disparity error (px) |"
          + (" Receiver hidden by the boom (%) |" if boom else ""))
    print("|---|---|---:|" + "---:|" * (len(COMPONENTS) + 3 + (1 if boom else 0)))
    for region in ("A", "B", "C"):
        for label, frames in runs:
            rows = [frames[i] for i in sorted(common) if frames[i]["region"] == region]
            ok = [r for r in rows if r["status"] == "ok"]
            mae = [sum(abs(r["err_" + c]) for r in ok) / len(ok) if ok else None for c in COMPONENTS]
            truth = [r for r in rows if r.get("truth_points") is not None]
            points = sum(r["truth_points"] for r in truth)
            off_rec = sum(r["truth_off_receiver"] for r in truth)
            off_surf = sum(r["truth_off_surface"] for r in truth)
            on = points - off_rec
            sq = sum(r["truth_error_squared_sum_px2"] for r in truth)
            cells = [fmt(v, 3) for v in mae]
            cells += [fmt(100.0 * off_rec / points, 2) if points else "-",
                      fmt(100.0 * off_surf / points, 2) if points else "-",
                      fmt(math.sqrt(sq / on), 3) if on > 0 else "-"]
            if boom:
                hidden = [r["receiver_occluded_fraction"] for r in rows
                          if r.get("receiver_occluded_fraction") is not None]
                cells.append(fmt(100.0 * sum(hidden) / len(hidden), 2) if hidden else "-")
            print(f"| {region} | {label} | {len(ok)}/{len(rows)} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
