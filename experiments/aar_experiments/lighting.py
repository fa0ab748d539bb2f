"""Lighting: the estimator's error against where the sun is.

Every dataset of the other experiments is lit by one sun, 52 deg left of the
tanker's heading and 55 deg up. Here the same CONOPS frames (regions B and C)
are rendered with the sun at three elevations (10, 30 and 60 deg) and three
azimuths from the tanker's heading (0: ahead of the tanker, lighting the
receiver's nose and the front of its wings; 90: to the right; 180: aft,
behind the receiver, towards where the cameras look), `aar-render render
--sun-azimuth A --sun-elevation E`, over the flat sky, with depth truth, and
analyzed with the default preset and the dataset's exact calibration (only
the images change). Each sun lights the aircraft twice: with the matte
shading every other dataset has, and with `--shading pbr` (the models' glTF
materials: the C-12's gloss paint reflects the sun and the sky). Per region,
sun and shading: the mean absolute error of each degree of freedom, its
ratio to the default sun's matte one, and the stages against the depth truth
(the sensed points' disparity error, points per frame, the signed x and
pitch).
"""

import json

from .outputs import read_frames
from .realism import region_results
from .registry import register
from .report import Report, conclude, fmt
from .runner import analyze, render_frames, selection_text
from .thesis import COMPONENT_HEADERS

CONOPS = "flightpaths/conops.csv"
PRESET = ("--preset", "default")
MSAA = {"quick": 4, "full": 16}
SELECTION = {"quick": ("frames", "586:588"), "full": ("frames", "118:609", "0/10")}
# (azimuth from the heading, elevation) [deg]; None: the default sun.
SUNS = {"quick": (None, (180, 30)),
        "full": (None, (0, 10), (0, 30), (0, 60), (90, 10), (90, 30), (90, 60), (180, 10), (180, 30), (180, 60))}
REGIONS = ("B", "C")
# (sun, shading) pairs rendered: every sun with both shadings; --quick adds pbr for the default sun only.
SHADINGS = ("matte", "pbr")


def _cases(mode):
    if mode == "quick":
        return [(sun, "matte") for sun in SUNS[mode]] + [(None, "pbr")]
    return [(sun, shading) for sun in SUNS[mode] for shading in SHADINGS]


def _label(sun, shading):
    text = "default (52 left, 55 up)" if sun is None else f"azimuth {sun[0]}, elevation {sun[1]}"
    return text if shading == "matte" else f"{text}, pbr"


def _key(sun, shading):
    text = "default" if sun is None else f"az{sun[0]}-el{sun[1]}"
    return text if shading == "matte" else f"{text}-pbr"


@register("lighting", order=8,
          help="beyond the thesis: the pose error against the sun's azimuth and elevation (regions B and C, "
               "every 10th frame at x16, matte and pbr shading; --quick: two frames at x4, two suns)")
def run(ctx):
    mode = "quick" if ctx.quick else "full"
    msaa, sel = MSAA[mode], SELECTION[mode]
    rep = Report(ctx, "Lighting: the pose error against where the sun is")
    rep.p(__doc__.split("\n\n", 1)[1].strip().replace("\n", " "))
    rep.p(f"{selection_text(sel)}, x{msaa}, shelled model, `--preset default`, each dataset's "
          "`calibration_ideal.yaml`; mean absolute errors in m and deg.")
    results, run_dirs = {}, []
    for sun, shading in _cases(mode):
        key = _key(sun, shading)
        dataset = ctx.dataset(f"lighting-{key}-x{msaa}")
        extra = ("--depth",) + (() if sun is None else ("--sun-azimuth", str(sun[0]), "--sun-elevation", str(sun[1])))
        if shading != "matte":
            extra += ("--shading", shading)
        render_frames(ctx, dataset, msaa, CONOPS, sel, extra=extra)
        out = analyze(ctx, f"lighting-{key}", dataset, "shelled", sel,
                      calibration=dataset / "calibration_ideal.yaml", extra=PRESET)
        run_dirs.append(out)
        results[key] = {"sun": sun, "shading": shading, "regions": region_results(out),
                        "frames": len(read_frames(out))}
    base = results["default"]["regions"]
    for region in REGIONS:
        if region not in base:
            continue
        rep.h(f"Region {region}")
        rows, stage_rows = [], []
        for sun, shading in _cases(mode):
            r = results[_key(sun, shading)]["regions"].get(region)
            if r is None or r["mae"] is None:
                continue
            ratios = [(v / b if b else None) for v, b in zip(r["mae"], base[region]["mae"])]
            base_case = sun is None and shading == "matte"
            rows.append([_label(sun, shading)] + [fmt(v) + ("" if base_case or q is None else f" ({q:.2f})")
                                         for v, q in zip(r["mae"], ratios)] + [f"{r['ok']}/{r['frames']}"])
            st = r["stages"]
            if st is None:
                continue
            stage_rows.append([_label(sun, shading), fmt(st["disparity_mean_px"], 4), fmt(st["disparity_rms_px"], 4),
                               f"{st['points_per_frame']:.0f}", f"{st['signed_x_m']:+.3f}",
                               f"{st['signed_pitch_deg']:+.3f}"])
        rep.p("Mean absolute error; in parentheses the ratio to the default sun's with matte shading.")
        rep.table(["Sun"] + list(COMPONENT_HEADERS) + ["Frames ok/all"], rows,
                  ["---"] + ["---:"] * (len(COMPONENT_HEADERS) + 1))
        rep.p("Stages against the depth truth: the disparity error of the sensed points on the receiver, the "
              "points per frame, and the signed mean errors of x and pitch.")
        rep.table(["Sun", "Disparity mean (px)", "Disparity RMS (px)", "Points per frame", "Signed X (m)",
                   "Signed pitch (deg)"], stage_rows, ["---"] + ["---:"] * 5)
    (ctx.out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    return conclude(ctx, rep, run_dirs)
