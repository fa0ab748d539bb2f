"""Rolling shutter: the estimator's error when the rows are read out one after the other.

The analyzer takes each frame as one instant, the sample's time. A rolling
shutter exposes row r of H at `readout * ((r + 0.5) / H - 0.5)` from it
(docs/rendering.md, "Rolling shutter"), so a receiver that moves relative to
the cameras is seen at a different instant in each row: skewed where it
crosses the image, stretched or squeezed where it closes. The same CONOPS
frames are rendered through `scenes/rig.json`'s cameras and a noise-free
sensor (10^7 e- at radiance 1, no read noise or fixed pattern, a 16-bit ADC:
the readout is the only change), with a global shutter and readouts of 10
and 30 ms (`sensor.readout_ms`; `--readout-bands 32`, the default), with
depth truth, and analyzed with the default preset and the dataset's exact
calibration. Per region and readout: the mean absolute error of each degree
of freedom, its ratio to the global shutter's, and the stages against the
depth truth, which is composed band by band as the images are (each row's
truth at its own instant), so a disparity error that does not grow says the
images and the truth agree; the pose's error is then the frame-as-an-instant
assumption's.
"""

import json

from .outputs import read_frames
from .realism import NOISE_FREE_SENSOR, region_results
from .registry import register
from .report import Report, conclude, fmt
from .runner import ROOT, analyze, render_frames, selection_text
from .thesis import COMPONENT_HEADERS

CONOPS = "flightpaths/conops.csv"
RIG = "scenes/rig.json"
PRESET = ("--preset", "default")
MSAA = {"quick": 4, "full": 16}
SELECTION = {"quick": ("frames", "586:588"), "full": ("frames", "0:609", "0/10")}
READOUTS_MS = {"quick": (0, 30), "full": (0, 10, 30)}


def _label(readout_ms):
    return "global shutter" if readout_ms == 0 else f"rolling, {readout_ms} ms readout"


def readout_rig(ctx, readout_ms):
    """OUT/rig-readout-<ms>.json: scenes/rig.json's cameras with NOISE_FREE_SENSOR and that readout (0: a
    global shutter)."""
    rig = json.loads((ROOT / RIG).read_text())
    rig["schema"] = "aar-rig/3"
    rig["sensor"] = dict(NOISE_FREE_SENSOR)
    if readout_ms > 0:
        rig["sensor"]["readout_ms"] = float(readout_ms)
    rig["description"] = (f"{RIG}'s cameras with a noise-free sensor and a {_label(readout_ms)}, written by "
                          "experiments/aar_experiment.py rolling-shutter")
    path = ctx.out / f"rig-readout-{readout_ms}.json"
    path.write_text(json.dumps(rig, indent=2) + "\n")
    return path


@register("rolling-shutter", order=9,
          help="beyond the thesis: the pose error with a rolling shutter (global, 10 and 30 ms readouts; every 10th "
               "CONOPS frame at x16; --quick: two frames at x4, global and 30 ms)")
def run(ctx):
    mode = "quick" if ctx.quick else "full"
    msaa, sel = MSAA[mode], SELECTION[mode]
    rep = Report(ctx, "Rolling shutter: the pose error when the rows are read out one after the other")
    rep.p(__doc__.split("\n\n", 1)[1].strip().replace("\n", " "))
    rep.p(f"{selection_text(sel)}, x{msaa}, shelled model, `--preset default`, each dataset's "
          "`calibration_ideal.yaml`; mean absolute errors in m and deg.")
    results, run_dirs = {}, []
    for readout_ms in READOUTS_MS[mode]:
        key = f"readout-{readout_ms}"
        dataset = ctx.dataset(f"rolling-{key}-x{msaa}")
        render_frames(ctx, dataset, msaa, CONOPS, sel, extra=("--depth", "--rig", readout_rig(ctx, readout_ms)))
        out = analyze(ctx, f"rolling-{key}", dataset, "shelled", sel,
                      calibration=dataset / "calibration_ideal.yaml", extra=PRESET)
        run_dirs.append(out)
        results[key] = {"readout_ms": readout_ms, "regions": region_results(out), "frames": len(read_frames(out))}
    base = results["readout-0"]["regions"]
    for region in ("A", "B", "C"):
        if region not in base:
            continue
        rep.h(f"Region {region}")
        rows, stage_rows = [], []
        for readout_ms in READOUTS_MS[mode]:
            r = results[f"readout-{readout_ms}"]["regions"].get(region)
            if r is None or r["mae"] is None:
                continue
            ratios = [(v / b if b else None) for v, b in zip(r["mae"], base[region]["mae"])]
            rows.append([_label(readout_ms)]
                        + [fmt(v) + ("" if readout_ms == 0 or q is None else f" ({q:.2f})")
                           for v, q in zip(r["mae"], ratios)] + [f"{r['ok']}/{r['frames']}"])
            st = r["stages"]
            if st is None:
                continue
            stage_rows.append([_label(readout_ms), fmt(st["disparity_mean_px"], 4), fmt(st["disparity_rms_px"], 4),
                               f"{st['points_per_frame']:.0f}", f"{st['signed_x_m']:+.3f}",
                               f"{st['signed_pitch_deg']:+.3f}"])
        rep.p("Mean absolute error; in parentheses the ratio to the global shutter's.")
        rep.table(["Shutter"] + list(COMPONENT_HEADERS) + ["Frames ok/all"], rows,
                  ["---"] + ["---:"] * (len(COMPONENT_HEADERS) + 1))
        rep.p("Stages against the depth truth: the disparity error of the sensed points on the receiver, the "
              "points per frame, and the signed mean errors of x and pitch.")
        rep.table(["Shutter", "Disparity mean (px)", "Disparity RMS (px)", "Points per frame", "Signed X (m)",
                   "Signed pitch (deg)"], stage_rows, ["---"] + ["---:"] * 5)
    (ctx.out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    return conclude(ctx, rep, run_dirs)
