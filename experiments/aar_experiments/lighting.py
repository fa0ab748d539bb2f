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

Then the realistic light: the same frames over the procedural terrain, first
with the fixed light (the baseline of this group), then with `--daylight`
(the sun's colour and brightness after the atmosphere, Preetham's sky, the
aircraft lit by that sky and by the ground; docs/rendering.md, "Daylight"),
then with daylight, the glTF materials and the sun's shadows (`--shading pbr
--shadows`) for the default sun and four others, and the sun in view: the
tanker pitched 10 deg nose down and the sun 2 deg up aft, its disc near the
top of the image.

Then the night, through the full sensor model (`scenes/rig-noisy.json`:
shot and read noise, blur, RGGB mosaic), whose noise at low light is what
makes it honest: the baseline is that rig by day over the terrain with
daylight; at night a full moon (0.25 lx) and the receiver's lights
(`--night --receiver-lights`), the camera's exposure 6 EV above the rig's
(`--exposure-ev 6`: a 4 ms shutter at f/1.4 against the day's 0.5 ms at
f/4), with the tanker's floodlight giving 400 lx or 100 lx at the contact
position, or with the moon alone; and with the floodlight at 100 lx the
camera's auto-exposure (`--auto-exposure --ae-max-ev 9`, from EV 6: it
meters the whole, mostly dark image and so runs to its limit, 9 EV above
the rig's, a 33 ms shutter at f/1.4 against the day's 0.5 ms at f/4).

Then the sun in view through the sensor (`scenes/rig-noisy.json` over the
terrain with daylight, pbr and shadows, the tanker pitched 10 deg nose
down, the sun 2 deg up aft), its lens's stray light added one effect at a
time in rigs the experiment writes (OUT/rig-stray-*.json): the sun's veil
(`glare_fraction` 0.02, the glare tests' value), then three flare ghosts
(at -0.4, -0.9 and -1.5 of the way from the centre to the sun, 12, 30 and
60 px, fractions 5e-5, 2e-5 and 1e-5: two reflections of about 0.5 % off
single-coated surfaces), then a CCD's blooming and smear (`blooming` 1, no
anti-blooming drain; `smear` 0.001).

Then the thermal camera: the same frames through `scenes/rig-lwir.json`,
an uncooled 8-14 um pair at 640 x 512 (NETD 50 mK) in the visible rig's
place, over the flat sky at 220 K, the skins at the airflow's recovery
temperature (249 K) and the nacelles 40 K warmer (docs/rendering.md,
"Thermal camera"), against the visible camera's default sun over the flat
sky.
"""

import json

from .outputs import read_frames
from .realism import region_results
from .registry import register
from .report import Report, conclude, fmt
from .runner import ROOT, analyze, rel, render_frames, selection_text
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
TERRAIN = ("--background", "terrain")
REALISTIC = TERRAIN + ("--daylight", "--shading", "pbr", "--shadows")
# Over terrain: (key, label, render flags); the first is the group's baseline.
TERRAIN_CASES = {
    "quick": (("terrain", "fixed light", TERRAIN),
              ("terrain-daylight-pbr-shadows", "daylight, pbr, shadows", REALISTIC)),
    "full": (("terrain", "fixed light", TERRAIN),
             ("terrain-daylight", "daylight", TERRAIN + ("--daylight",)),
             ("terrain-daylight-pbr-shadows", "daylight, pbr, shadows", REALISTIC),
             ("terrain-az0-el10", "daylight, pbr, shadows, azimuth 0, elevation 10",
              REALISTIC + ("--sun-azimuth", "0", "--sun-elevation", "10")),
             ("terrain-az90-el30", "daylight, pbr, shadows, azimuth 90, elevation 30",
              REALISTIC + ("--sun-azimuth", "90", "--sun-elevation", "30")),
             ("terrain-az180-el10", "daylight, pbr, shadows, azimuth 180, elevation 10",
              REALISTIC + ("--sun-azimuth", "180", "--sun-elevation", "10")),
             ("terrain-az180-el30", "daylight, pbr, shadows, azimuth 180, elevation 30",
              REALISTIC + ("--sun-azimuth", "180", "--sun-elevation", "30")),
             ("terrain-sun-in-view", "daylight, pbr, shadows, sun in view (tanker pitch 10, azimuth 180, elevation 2)",
              REALISTIC + ("--tanker-pitch", "10", "--sun-azimuth", "180", "--sun-elevation", "2"))),
}
NOISY = ("--rig", "scenes/rig-noisy.json")
NIGHT = NOISY + TERRAIN + ("--night", "--receiver-lights", "--exposure-ev", "6")
# At night, through the sensor model: (key, label, render flags); the first is the group's baseline.
NIGHT_CASES = {
    "quick": (("night-day", "by day (daylight)", NOISY + TERRAIN + ("--daylight",)),
              ("night-flood-400", "night, floodlight 400 lx", NIGHT + ("--floodlight", "400"))),
    "full": (("night-day", "by day (daylight)", NOISY + TERRAIN + ("--daylight",)),
             ("night-flood-400", "night, floodlight 400 lx", NIGHT + ("--floodlight", "400")),
             ("night-flood-100", "night, floodlight 100 lx", NIGHT + ("--floodlight", "100")),
             ("night-flood-100-ae", "night, floodlight 100 lx, auto-exposure (at most 9 EV)",
              NIGHT + ("--floodlight", "100", "--auto-exposure", "--ae-max-ev", "9")),
             ("night-moon", "night, full moon alone", NIGHT)),
}
SUN_IN_VIEW = ("--tanker-pitch", "10", "--sun-azimuth", "180", "--sun-elevation", "2")
# The lens's stray light and the sensor's charge spill, added one at a time to scenes/rig-noisy.json's sensor.
GHOSTS = [{"position": -0.4, "radius_px": 12.0, "fraction": 5e-5},
          {"position": -0.9, "radius_px": 30.0, "fraction": 2e-5},
          {"position": -1.5, "radius_px": 60.0, "fraction": 1e-5}]
STRAY_SENSORS = {
    "glare": {"glare_fraction": 0.02},
    "flare": {"glare_fraction": 0.02, "flare_ghosts": GHOSTS},
    "bloom": {"glare_fraction": 0.02, "flare_ghosts": GHOSTS, "blooming": 1.0, "smear": 0.001},
}
# The sun in view through the sensor: (key, label, rig part or None for scenes/rig-noisy.json); the first the baseline.
STRAY_CASES = {
    "quick": (("stray-none", "rig-noisy, sun in view", None),
              ("stray-bloom", "+ glare, ghosts, blooming and smear", "bloom")),
    "full": (("stray-none", "rig-noisy, sun in view", None),
             ("stray-glare", "+ veiling glare", "glare"),
             ("stray-flare", "+ glare and flare ghosts", "flare"),
             ("stray-bloom", "+ glare, ghosts, blooming and smear", "bloom")),
}


# The thermal camera: (key, label, render flags), against the visible default sun over the flat sky.
THERMAL_CASES = {
    "quick": (("lwir", "LWIR 8-14 um, NETD 50 mK (scenes/rig-lwir.json)", ("--rig", "scenes/rig-lwir.json")),),
    "full": (("lwir", "LWIR 8-14 um, NETD 50 mK (scenes/rig-lwir.json)", ("--rig", "scenes/rig-lwir.json")),
             ("lwir-cold-nacelles", "LWIR, nacelles at the skin's temperature (engines off)",
              ("--rig", "scenes/rig-lwir.json", "--nacelle-excess", "0"))),
}


def stray_rig(ctx, part):
    """OUT/rig-stray-<part>.json: scenes/rig-noisy.json with STRAY_SENSORS[part] in its sensor block."""
    if part is None:
        return NOISY[1]
    rig = json.loads((ROOT / NOISY[1]).read_text())
    rig["sensor"].update(STRAY_SENSORS[part])
    rig["description"] = (f"{NOISY[1]} with {', '.join(sorted(STRAY_SENSORS[part]))} in its sensor block, written by "
                          "experiments/aar_experiment.py lighting")
    path = ctx.out / f"rig-stray-{part}.json"
    path.write_text(json.dumps(rig, indent=2) + "\n")
    return path


def _flat_render_flags(sun, shading):
    extra = () if sun is None else ("--sun-azimuth", str(sun[0]), "--sun-elevation", str(sun[1]))
    return extra + (() if shading == "matte" else ("--shading", shading))


def _cases(mode):
    """(group, key, label, render flags) of every dataset, the flat sky's first."""
    if mode == "quick":
        flat = [(sun, "matte") for sun in SUNS[mode]] + [(None, "pbr")]
    else:
        flat = [(sun, shading) for sun in SUNS[mode] for shading in SHADINGS]
    cases = [("flat", _key(sun, shading), _label(sun, shading), _flat_render_flags(sun, shading))
             for sun, shading in flat]
    return (cases + [("terrain", key, label, flags) for key, label, flags in TERRAIN_CASES[mode]] +
            [("night", key, label, flags) for key, label, flags in NIGHT_CASES[mode]] +
            [("stray", key, label, part) for key, label, part in STRAY_CASES[mode]] +
            [("thermal", key, label, flags) for key, label, flags in THERMAL_CASES[mode]])


def _label(sun, shading):
    text = "default (52 left, 55 up)" if sun is None else f"azimuth {sun[0]}, elevation {sun[1]}"
    return text if shading == "matte" else f"{text}, pbr"


def _key(sun, shading):
    text = "default" if sun is None else f"az{sun[0]}-el{sun[1]}"
    return text if shading == "matte" else f"{text}-pbr"


GROUPS = (("flat", "default", "over the flat sky, the fixed light",
           "in parentheses the ratio to the default sun's with matte shading"),
          ("terrain", "terrain", "over terrain, daylight and shadows",
           "in parentheses the ratio to the fixed light over the same terrain"),
          ("night", "night-day", "at night, through the sensor model",
           "in parentheses the ratio to the same sensor by day"),
          ("stray", "stray-none", "the sun in view through the lens and sensor",
           "in parentheses the ratio to the same rig without stray light"),
          ("thermal", "default", "the thermal camera over the flat sky",
           "in parentheses the ratio to the visible camera's (the first row)"))


@register("lighting", order=8,
          help="beyond the thesis: the pose error against the sun's azimuth and elevation (regions B and C, "
               "every 10th frame at x16, matte and pbr shading), and over terrain with daylight, shadows and the "
               "sun in view, at night with the moon, the receiver's lights and the tanker's floodlight through the "
               "sensor model, the sun in view with the lens's glare and ghosts and a CCD's blooming, and through the "
               "thermal camera; --quick: two frames at x4, two suns, two terrain, two night, two stray-light cases "
               "and the thermal camera)")
def run(ctx):
    mode = "quick" if ctx.quick else "full"
    msaa, sel = MSAA[mode], SELECTION[mode]
    rep = Report(ctx, "Lighting: the pose error against where the sun is")
    rep.p(__doc__.split("\n\n", 1)[1].strip().replace("\n", " "))
    rep.p(f"{selection_text(sel)}, x{msaa}, shelled model, `--preset default`, each dataset's "
          "`calibration_ideal.yaml`; mean absolute errors in m and deg.")
    results, run_dirs = {}, []
    for group, key, label, flags in _cases(mode):
        if group == "stray":
            flags = ("--rig", rel(stray_rig(ctx, flags))) + REALISTIC + SUN_IN_VIEW
        dataset = ctx.dataset(f"lighting-{key}-x{msaa}")
        render_frames(ctx, dataset, msaa, CONOPS, sel, extra=("--depth",) + flags)
        out = analyze(ctx, f"lighting-{key}", dataset, "shelled", sel,
                      calibration=dataset / "calibration_ideal.yaml", extra=PRESET)
        run_dirs.append(out)
        results[key] = {"group": group, "label": label, "render_flags": list(flags),
                        "regions": region_results(out), "frames": len(read_frames(out))}
    for group, base_key, title, ratio_text in GROUPS:
        base = results[base_key]["regions"]
        cases = [c for c in _cases(mode) if c[0] == group]
        if all(key != base_key for _, key, _, _ in cases):  # a baseline from another group heads the table
            cases = [c for c in _cases(mode) if c[1] == base_key] + cases
        for region in REGIONS:
            if region not in base:
                continue
            rep.h(f"Region {region}, {title}")
            rows, stage_rows = [], []
            for _, key, label, _ in cases:
                r = results[key]["regions"].get(region)
                if r is None:
                    continue
                if r["mae"] is None:
                    rows.append([label] + ["-"] * len(COMPONENT_HEADERS) + [f"{r['ok']}/{r['frames']}"])
                    continue
                ratios = [(v / b if b else None) for v, b in zip(r["mae"], base[region]["mae"])]
                rows.append([label] + [fmt(v) + ("" if key == base_key or q is None else f" ({q:.2f})")
                                       for v, q in zip(r["mae"], ratios)] + [f"{r['ok']}/{r['frames']}"])
                st = r["stages"]
                if st is None:
                    continue
                stage_rows.append([label, fmt(st["disparity_mean_px"], 4), fmt(st["disparity_rms_px"], 4),
                                   f"{st['points_per_frame']:.0f}", f"{st['signed_x_m']:+.3f}",
                                   f"{st['signed_pitch_deg']:+.3f}"])
            rep.p(f"Mean absolute error; {ratio_text}.")
            rep.table(["Sun"] + list(COMPONENT_HEADERS) + ["Frames ok/all"], rows,
                      ["---"] + ["---:"] * (len(COMPONENT_HEADERS) + 1))
            rep.p("Stages against the depth truth: the disparity error of the sensed points on the receiver, the "
                  "points per frame, and the signed mean errors of x and pitch.")
            rep.table(["Sun", "Disparity mean (px)", "Disparity RMS (px)", "Points per frame", "Signed X (m)",
                       "Signed pitch (deg)"], stage_rows, ["---"] + ["---:"] * 5)
    (ctx.out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    return conclude(ctx, rep, run_dirs)
