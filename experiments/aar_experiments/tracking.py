"""Tracking at the camera's rate: the temporal filter on consecutive frames of a realistic sensor.

The committed paths sample the approach every 0.5 s; a tanker's camera runs at
125 Hz, where consecutive estimates share most of their motion and the
temporal filter (docs/analysis.md, "The temporal filter") has frames to work
with. The CONOPS approach is generated again at 0.008 s steps
(`aar-make-flightpaths --time-step 0.008`), and three segments of consecutive
frames, one per region, are rendered through scenes/rig-noisy.json (the
EMVA 1288 sensor: shot and read noise, blur, the RGGB mosaic, drawn afresh
every frame) and analyzed with the default preset in tracking mode
(`--track`), with the dataset's exact calibration (the calibration is not
what this measures).

Per segment and degree of freedom the report gives the mean absolute error
per frame and filtered, the jitter (RMS change of the error from one frame to
the next) per frame and filtered, and the filter's lag behind the per-frame
estimates: the time shift that best explains their difference as the truth's
motion, -sum((filtered - estimate) v) / sum(v^2) with v the truth's change per
frame, in frames, with its standard error (it is only defined where the truth
moves more than the noise over the segment).
"""

import math

from .outputs import ok_rows, read_frames, read_summary
from .registry import register
from .report import Report, conclude, fmt
from .runner import ROOT, analyze, render_frames
from .thesis import COMPONENT_HEADERS, COMPONENTS

RIG_NOISY = "scenes/rig-noisy.json"
TIME_STEP_S = "0.008"  # 125 Hz
MSAA = 4               # the device's native level: the sensor's noise and blur dominate the edges here
# (region, first frame of the 125 Hz path, what the receiver does there); the segments are the frames
# first .. first + count - 1.
SEGMENTS = (("A", 5000, "closing at about 2 m/s, 40 s into the approach"),
            ("B", 20625, "closing at about 0.5 m/s towards the hold near 34 m"),
            ("C", 25000, "holding near 34 m, weaving in attitude"))
COUNT = {"quick": 25, "full": 250}


def _path(ctx):
    """The CONOPS approach at 125 Hz, written by aar-make-flightpaths into the datasets folder."""
    out = ctx.datasets / "paths-125hz"
    ctx.run("generate the CONOPS approach at 125 Hz",
            [ctx.make_flightpaths, "--rig", ROOT / "scenes/rig.json", "--out", out, "--paths", "conops",
             "--time-step", TIME_STEP_S])
    return out / "conops.csv"


def _lag(rows, component):
    """(lag in frames, its standard error) of the filtered estimates behind the per-frame ones; None where the
    truth does not move."""
    products, speeds = [], []
    for a, b in zip(rows, rows[1:]):
        if b["frame"] - a["frame"] != 1:
            continue
        v = b["truth_" + component] - a["truth_" + component]
        if component.endswith("_deg"):
            v = (v + 180.0) % 360.0 - 180.0
        products.append((b["filt_est_" + component] - b["est_" + component]) * v)
        speeds.append(v * v)
    total = sum(speeds)
    if total == 0.0:
        return None
    lag = -sum(products) / total
    residuals = [p - (-lag) * s for p, s in zip(products, speeds)]
    return lag, math.sqrt(sum(r * r for r in residuals)) / total


def _rows(summary, frames, region):
    g = summary["models"]["shelled"][region]
    ok = ok_rows(frames)
    lags = [_lag(ok, c) for c in COMPONENTS]
    cells = [
        ("error, per frame", [fmt(g["mean_abs_error"][c]) for c in COMPONENTS]),
        ("error, filtered", [fmt(g["filtered_mean_abs_error"][c]) for c in COMPONENTS]),
        ("jitter, per frame", [fmt(g["jitter_rms"][c]) for c in COMPONENTS]),
        ("jitter, filtered", [fmt(g["filtered_jitter_rms"][c]) for c in COMPONENTS]),
        ("lag (frames)", [f"{lag:+.2f} ± {se:.2f}" if lag is not None else "n/a" for lag, se in
                          (x if x is not None else (None, None) for x in lags)]),
    ]
    return g, cells


@register("tracking", order=6,
          help="beyond the thesis: the temporal filter at 125 Hz on a realistic sensor in tracking mode (error, "
               "jitter, lag)")
def run(ctx):
    path = _path(ctx)
    count = COUNT["quick" if ctx.quick else "full"]
    rep = Report(ctx, "Tracking at the camera's rate: the temporal filter")
    rep.p(__doc__.split("\n\n", 1)[1].strip().replace("\n", " "))
    rep.p(f"{count} consecutive frames per segment (x{MSAA}), shelled model, `--preset default`, the dataset's "
          "`calibration_ideal.yaml`. The filter is the analyzer's default (`--filter-window 0.1`: 13 frames at "
          "125 Hz). Errors and jitter in m and deg; `summary.json` and `frames.csv` of each run.")
    run_dirs = []
    for region, first, what in SEGMENTS:
        selection = ("frames", f"{first}:{first + count}")
        dataset = ctx.dataset(f"tracking-125hz-{region}")
        render_frames(ctx, dataset, MSAA, path, selection, extra=("--rig", RIG_NOISY))
        out = analyze(ctx, f"tracking-{region}", dataset, "shelled", selection,
                      calibration=dataset / "calibration_ideal.yaml", extra=("--preset", "default", "--track"))
        run_dirs.append(out)
        g, cells = _rows(read_summary(out), read_frames(out), region)
        rep.h(f"Region {region}: {what} (frames {first}-{first + count - 1}; {g['ok']} of {g['frames']} measured, "
              f"{g['jitter_pairs']} consecutive pairs)")
        rep.table(["", *COMPONENT_HEADERS], [[label, *values] for label, values in cells],
                  ["---"] + ["---:"] * len(COMPONENTS))
    return conclude(ctx, rep, run_dirs)
