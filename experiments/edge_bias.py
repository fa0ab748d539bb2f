#!/usr/bin/python3
"""The sensed disparities' error against depth truth by distance to the receiver's outline.

    experiments/edge_bias.py RUN_DIR [RUN_DIR ...] [--pixels-of RUN_DIR]

Reads the frame dumps of `aar-analyze run --dump-frames ...` on a dataset
rendered with --depth: per dumped frame, NNNNNN_points.csv (every sensed
point's rectified pixel, disparity and true disparity) and
NNNNNN_disparity.png (black where the frame has no disparity). A point's
distance to the outline is its Chebyshev distance (as the halo removal
measures) to the nearest pixel without a disparity that is connected to the
image's border through pixels without one: holes inside the receiver, where
matching failed on its surface, are not its outline. Against the flat sky
that is the receiver's outline after the halo removal; a textured
background has disparities of its own and the distance loses its meaning. Prints, per run, the points on the receiver, their mean error and,
per distance band, the mean error and the share of the points [%].

With --pixels-of OTHER, also the mean error of each run on only the pixels
(frame, rounded u and v) that OTHER kept too, and OTHER's on the same pixels:
run on the same frames and rig geometry, it separates which pixels a run
keeps from how it measures them (docs/analysis.md, "The cloud's edge").
Reads the runs with python/aar_stereo (NumPy, PIL).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))
import aar_stereo  # noqa: E402

BANDS = (0, 3, 5, 7, 9, 12, 16)


def shifted(mask, dy, dx, fill):
    """mask moved by (dy, dx), `fill` where it moved in from outside."""
    out = np.full_like(mask, fill)
    h, w = mask.shape
    out[max(dy, 0):h + min(dy, 0), max(dx, 0):w + min(dx, 0)] = mask[max(-dy, 0):h - max(dy, 0),
                                                                     max(-dx, 0):w - max(dx, 0)]
    return out


def outline_distance(valid):
    """Chebyshev distance of each pixel to the outside (no disparity, connected to the border), capped at 99."""
    outside = np.zeros_like(valid)
    outside[0, :], outside[-1, :], outside[:, 0], outside[:, -1] = (~valid[0, :], ~valid[-1, :], ~valid[:, 0],
                                                                      ~valid[:, -1])
    while True:  # flood fill through the pixels without a disparity (4-connected)
        grown = outside.copy()
        for dy, dx in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            grown |= shifted(outside, dy, dx, False)
        grown &= ~valid
        if np.array_equal(grown, outside):
            break
        outside = grown
    distance = np.full(valid.shape, 99, dtype=np.int32)
    reached = outside.copy()
    for d in range(99):
        distance[reached & (distance == 99)] = d
        if reached.all():
            break
        grown = reached.copy()
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                grown |= shifted(reached, dy, dx, False)
        reached = grown
    return distance


def frame_points(run):
    """(frame, u, v, error, distance) of every point on the receiver of every dumped frame."""
    dumps = [d for d in aar_stereo.open_run(run).dumps.values() if "points" in d.files]
    if not dumps:
        raise SystemExit(f"{run}: no frames/*_points.csv (run with --dump-frames on a dataset with --depth)")
    out = []
    for dump in dumps:
        distance_map = outline_distance(dump.disparity().sum(axis=2) > 0)
        points = dump.points()
        on = ~np.isnan(points["true_disparity_px"])
        us, vs = (np.rint(points[c][on]).astype(int) for c in ("u_px", "v_px"))
        errors = points["disparity_px"][on] - points["true_disparity_px"][on]
        out += [(dump.frame, u, v, error, distance_map[v, u]) for u, v, error in zip(us, vs, errors)]
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", metavar="RUN_DIR")
    parser.add_argument("--pixels-of", metavar="RUN_DIR", help="also compare on the pixels this run kept")
    args = parser.parse_args()
    bands = list(zip(BANDS, BANDS[1:] + (None,)))
    print("| run | points | mean error (px) | " +
          " | ".join(f"{a}-{b} px" if b else f">= {a} px" for a, b in bands) + " |")
    print("|---|---:|---:|" + "---:|" * len(bands))
    for run in args.runs:
        points = frame_points(run)
        errors = np.array([p[3] for p in points])
        distances = np.array([p[4] for p in points])
        cells = []
        for a, b in bands:
            inside = (distances >= a) & (distances < (b if b else np.inf))
            cells.append(f"{errors[inside].mean():+.4f} ({100 * inside.mean():.0f} %)" if inside.any() else "-")
        print(f"| {run} | {len(points)} | {errors.mean():+.4f} | " + " | ".join(cells) + " |")
    if args.pixels_of:
        other = {(p[0], p[1], p[2]): p[3] for p in frame_points(args.pixels_of)}
        print()
        print(f"| run | pixels also in {args.pixels_of} | its mean error there (px) | {args.pixels_of}'s there (px) |")
        print("|---|---:|---:|---:|")
        for run in args.runs:
            shared = [(p[3], other[(p[0], p[1], p[2])]) for p in frame_points(run) if (p[0], p[1], p[2]) in other]
            if not shared:
                print(f"| {run} | 0 | - | - |")
                continue
            mine, theirs = np.array(shared).T
            print(f"| {run} | {len(shared)} | {mine.mean():+.4f} | {theirs.mean():+.4f} |")


if __name__ == "__main__":
    main()
