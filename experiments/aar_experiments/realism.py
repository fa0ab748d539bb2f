"""Realism (issue 9, item 6): each sensor-realism effect alone, then all together, against the ideal scene.

The thesis's world (chapter V, 5.4) lacked a lens, a sensor, the boom, a
textured background, spinning propellers and motion blur. Each effect is
rendered alone on the same CONOPS frames, then all of them together, and
analyzed with the default preset and the shelled model:

  - with the calibration a tanker would have: its own 12 calibration boards
    rendered through the same rig (the rig effects: lens, sensor, all), else
    the baseline's boards (the effect does not change the board images);
  - with the dataset's exact calibration (calibration_ideal.yaml): the
    imaging alone, without the calibration's error;
  - for the boom and the propellers, which the default preset masks, also
    without the masks (`aar-analyze run --no-mask-boom`, `--no-mask-propellers`).

The sensor block is also split into its parts (noise alone, blur alone, the
Bayer mosaic alone, each through an otherwise noise-free sensor), and every
dataset is rendered with depth truth, so that each stage is measured where it
acts: the disparity error of the sensed points on the receiver, the fraction
of sensed points off the receiver or off its surface, and the signed error of
x and pitch beside the mean absolute ones.

The report has, per region, each degree of freedom's mean absolute error and
its ratio to the baseline's, the stage measurements, the calibrations' errors
against the rig, two kinds of figure and results.json. Propellers and motion blur need
`aar-render render --propellers` and `--shutter-ms`: the effects whose flags
this aar-render's `render --help` does not list are left out (and named so).
"""

import json
import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from . import realism_report
from .outputs import calibration_errors, group_counts, group_stats, ok_rows, read_frames, read_summary
from .registry import register
from .runner import ROOT, ExperimentError, analyze, calibrate, render_calib, render_frames

CONOPS = "flightpaths/conops.csv"
BOOM_PATH = "flightpaths/conops-boom.csv"
RIG = "scenes/rig.json"
RIG_DISTORTED = "scenes/rig-distorted.json"
RIG_NOISY = "scenes/rig-noisy.json"
PRESET = ("--preset", "default")  # the analyzer's default pipeline, named
PROPELLERS = ("--propellers", "1700")
SHUTTER = ("--shutter-ms", "4")
QUICK_TIME_SAMPLES = ("--time-samples", "4")  # --quick: 4 instants over the exposure, not the renderer's default
MSAA = {"quick": 4, "full": 16}
DEPTH = ("--depth",)  # every dataset: depth truth for the stage measurements
# A sensor with no noise worth the name: 10^7 e- at radiance 1 (shot noise 0.03 % of a mid-grey), no read noise or
# fixed pattern, a 16-bit ADC. With it, one part of scenes/rig-noisy.json's sensor is switched on at a time.
NOISE_FREE_SENSOR = {"exposure_e": 1.0e7, "full_well_e": 2.0e7, "read_noise_e": 0.0, "prnu": 0.0, "dsnu_e": 0.0,
                     "adc_bits": 16, "blur_sigma_px": 0.0, "bayer": "none"}


@dataclass
class Effect:
    key: str                  # table label, run and dataset names
    what: str                 # one line for the report
    rig: object = None        # rig JSON (None: aar-render's default, scenes/rig.json); also for its boards
    path: str = CONOPS        # flight path
    render: tuple = ()        # more aar-render render flags
    needs: tuple = ()         # aar-render render flags it needs (left out when not listed by --help)
    unmask: tuple = ()        # also analyzed with these aar-analyze flags (--no-mask-boom, --no-mask-propellers)
    suffix: str = ""          # appended to the dataset's name (a dataset per set of render flags)
    dataset: Path = None      # set by run()
    runs: dict = field(default_factory=dict)  # variant ("boards", "unmasked", "ideal") -> run folder


def render_flags(ctx):
    """The long options `aar-render render --help` lists."""
    out = subprocess.run([str(ctx.render), "render", "--help"], capture_output=True, text=True, cwd=ROOT)
    return set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", out.stdout))


def combined_rig(ctx):
    """OUT/rig-all.json: scenes/rig-noisy.json (its sensor block) with the lenses of scenes/rig-distorted.json;
    refused when the two rigs differ in anything else."""
    distorted = json.loads((ROOT / RIG_DISTORTED).read_text())
    noisy = json.loads((ROOT / RIG_NOISY).read_text())

    def bare(rig):
        rig = json.loads(json.dumps(rig))
        for k in ("schema", "description", "sensor"):
            rig.pop(k, None)
        for cam in rig["cameras"].values():
            cam.pop("distortion", None)
        return rig

    if bare(distorted) != bare(noisy):
        raise ExperimentError(f"realism: {RIG_DISTORTED} and {RIG_NOISY} differ in more than the lens and the "
                              "sensor; cannot combine them")
    rig = json.loads(json.dumps(noisy))
    rig["description"] = (f"{RIG_NOISY} (its sensor block) with the lenses of {RIG_DISTORTED}, written by "
                          "experiments/aar_experiment.py realism")
    for side, cam in rig["cameras"].items():
        cam["distortion"] = distorted["cameras"][side]["distortion"]
    path = ctx.out / "rig-all.json"
    path.write_text(json.dumps(rig, indent=2) + "\n")
    return path


def sensor_part_rig(ctx, part):
    """OUT/rig-sensor-<part>.json: scenes/rig-noisy.json with one part of its sensor block: "noise" (its photon
    transfer, no blur, no mosaic), "blur" or "mosaic" (that part alone through NOISE_FREE_SENSOR)."""
    rig = json.loads((ROOT / RIG_NOISY).read_text())
    sensor = rig["sensor"]
    if part == "noise":
        rig["sensor"] = dict(sensor, blur_sigma_px=0.0, bayer="none")
    elif part == "blur":
        rig["sensor"] = {**sensor, **NOISE_FREE_SENSOR, "blur_sigma_px": sensor["blur_sigma_px"]}
    else:
        rig["sensor"] = {**sensor, **NOISE_FREE_SENSOR, "bayer": sensor["bayer"]}
    rig["description"] = (f"{RIG_NOISY} with only the {part} of its sensor block, written by "
                          "experiments/aar_experiment.py realism")
    path = ctx.out / f"rig-sensor-{part}.json"
    path.write_text(json.dumps(rig, indent=2) + "\n")
    return path


def effect_table(ctx, flags):
    """(effects in report order, effects left out) for this aar-render's `render` flags."""
    shutter = SHUTTER + (QUICK_TIME_SAMPLES if ctx.quick and QUICK_TIME_SAMPLES[0] in flags else ())
    optional = [f for f in (PROPELLERS, shutter) if f[0] in flags]
    together = ("--background", "terrain") + tuple(x for f in optional for x in f)
    table = [
        Effect("baseline", "none: pinhole lens, noise-free sensor, no boom, flat sky (the thesis's world)"),
        Effect("distortion", f"lens distortion: `{RIG_DISTORTED}` (Brown-Conrady, barrel)", rig=RIG_DISTORTED),
        Effect("sensor", f"sensor model: `{RIG_NOISY}` (photon transfer noise, optical blur, Bayer mosaic)",
               rig=RIG_NOISY),
        Effect("sensor-noise", "the sensor's noise alone (photon transfer of `rig-noisy.json`, no blur, no mosaic)",
               rig=sensor_part_rig(ctx, "noise")),
        Effect("sensor-blur", "the sensor's optical blur alone (0.5 px Gaussian, a noise-free sensor)",
               rig=sensor_part_rig(ctx, "blur")),
        Effect("sensor-mosaic", "the sensor's RGGB mosaic and bilinear demosaicing alone (a noise-free sensor)",
               rig=sensor_part_rig(ctx, "mosaic")),
        Effect("boom", f"the refueling boom, posed by `{BOOM_PATH}`", path=BOOM_PATH, unmask=("--no-mask-boom",)),
        Effect("terrain", "terrain behind the receiver (`--background terrain`)", render=("--background", "terrain")),
        Effect("motion-blur", "motion blur: a 4 ms exposure (`--shutter-ms 4`)", render=shutter, needs=SHUTTER[:1]),
        Effect("propellers", "spinning propellers, 1700 rpm, 4 ms exposure", render=PROPELLERS + shutter,
               needs=(PROPELLERS[0], SHUTTER[0]), unmask=("--no-mask-propellers",)),
        Effect("all", "all together: lens and sensor (`rig-all.json`), boom, terrain"
               + "".join(f", `{' '.join(f)}`" for f in optional), rig=combined_rig(ctx), path=BOOM_PATH,
               render=together, unmask=("--no-mask-boom",) + (("--no-mask-propellers",) if PROPELLERS in optional else ()),
               suffix="".join("-" + f[0][2:] for f in optional)),
    ]
    used = [e for e in table if all(f in flags for f in e.needs)]
    left_out = [e for e in table if e not in used]
    return used, left_out


def dataset_name(effect, msaa):
    return f"realism-x{msaa}-{effect.key}{effect.suffix}"


def measure(ctx, effect, msaa, sel, baseline_calibration):
    """Renders and analyzes one effect; returns its calibration folder."""
    ds = effect.dataset = ctx.dataset(dataset_name(effect, msaa))
    rig_args = ("--rig", effect.rig) if effect.rig else ()
    cal = baseline_calibration
    if effect.rig or baseline_calibration is None:
        render_calib(ctx, ds, msaa, effect.rig)
        cal = calibrate(ctx, ds, ctx.out / "calibrations" / effect.key)
    render_frames(ctx, ds, msaa, effect.path, sel, tuple(effect.render) + DEPTH + rig_args)
    yaml = cal / "calibration.yaml"
    effect.runs["boards"] = analyze(ctx, effect.key, ds, "shelled", sel, calibration=yaml, extra=PRESET)
    effect.runs["ideal"] = analyze(ctx, f"{effect.key}-ideal", ds, "shelled", sel,
                                   calibration=ds / "calibration_ideal.yaml", extra=PRESET)
    if effect.unmask:
        effect.runs["unmasked"] = analyze(ctx, f"{effect.key}-unmasked", ds, "shelled", sel, calibration=yaml,
                                          extra=PRESET + tuple(effect.unmask))
    return cal


GROSS_DEG = 5.0  # an attitude error beyond this (any of roll, pitch, yaw) counts as a gross failure


def stage_results(rows):
    """The stages of the measured frames `rows` against the depth truth (frames.csv's truth_* columns): the
    disparity error of the sensed points on the receiver (mean and RMS, px), the fractions of sensed points off
    the receiver and off its surface, the fractions on the propeller blades and kept by the registration (the
    propeller mask's leftover), sensed points per frame, and the signed mean error of x (m) and pitch (deg)."""
    if not rows:
        return None
    points = sum(r["truth_points"] for r in rows)
    off_receiver = sum(r["truth_off_receiver"] for r in rows)
    on = points - off_receiver
    return {"disparity_mean_px": sum(r["truth_error_sum_px"] for r in rows) / on if on else None,
            "disparity_rms_px": (sum(r["truth_error_squared_sum_px2"] for r in rows) / on) ** 0.5 if on else None,
            "off_receiver": off_receiver / points if points else None,
            "off_surface": sum(r["truth_off_surface"] for r in rows) / points if points else None,
            "on_propellers": sum(r["truth_on_propellers"] for r in rows) / points if points else None,
            "propellers_kept": sum(r["truth_propellers_kept"] for r in rows) / points if points else None,
            "points_per_frame": sum(r["sensed_points"] for r in rows) / len(rows),
            "signed_x_m": sum(r["err_x_m"] for r in rows) / len(rows),
            "signed_pitch_deg": sum(r["err_pitch_deg"] for r in rows) / len(rows)}


def region_results(run_dir):
    """{region: {"mae": tuple in COMPONENTS order or None, "ok": n, "frames": n, "gross": n, "stages": dict or
    None}} for the regions analyzed; gross: measured frames with an attitude error beyond GROSS_DEG
    (frames.csv); stages: stage_results of its measured frames."""
    summary = read_summary(run_dir)
    rows = ok_rows(read_frames(run_dir))
    out = {}
    for region in ("A", "B", "C"):
        ok, frames = group_counts(summary, "shelled", region)
        if frames:
            mine = [r for r in rows if r["region"] == region]
            gross = sum(1 for r in mine if max(abs(r[f"err_{c}_deg"]) for c in ("roll", "pitch", "yaw")) > GROSS_DEG)
            out[region] = {"mae": group_stats(summary, "shelled", region, "mean_abs_error"), "ok": ok,
                           "frames": frames, "gross": gross, "stages": stage_results(mine)}
    return out


@register("realism", order=5,
          help="beyond the thesis: lens distortion, the sensor (and its noise, blur and mosaic alone), the boom, "
               "terrain, propellers and motion blur (when aar-render has them), each alone and all together: "
               "region errors, each stage against the depth truth, and calibration errors against the baseline "
               "(every 6th CONOPS frame at x16; --quick: four region-C frames at x4)")
def run(ctx):
    msaa = MSAA["quick" if ctx.quick else "full"]
    sel = ctx.sel["realism"]
    flags = render_flags(ctx)
    effects, left_out = effect_table(ctx, flags)
    calibrations = {}  # effect key -> calibration folder it was analyzed with
    for effect in effects:
        calibrations[effect.key] = measure(ctx, effect, msaa, sel, calibrations.get("baseline"))
    results = {"msaa": msaa, "selection": list(sel) if sel else None, "gross_deg": GROSS_DEG, "effects": {},
               "calibrations": {},
               "left_out": {e.key: [f for f in e.needs if f not in flags] for e in left_out}}
    for effect in effects:
        cal = calibrations[effect.key]
        if effect.rig or effect.key == "baseline":  # calibrated from its own boards
            results["calibrations"][effect.key] = calibration_errors(cal)
        results["effects"][effect.key] = {
            "what": effect.what, "dataset": effect.dataset.name,
            "calibration": effect.key if effect.rig else "baseline",
            "variants": {v: region_results(r) for v, r in effect.runs.items()}}
    (ctx.out / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    return realism_report.write(ctx, effects, left_out, results, sel)
