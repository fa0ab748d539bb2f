"""The realism experiment's report: the effects, the calibrations' errors, each region's errors against the
baseline's, the figures. Numbers come from results.json's dictionary (realism.run), which holds them as the
analyzer wrote them."""

import json

from . import plots
from .outputs import CALIBRATION_ERRORS
from .report import Report, conclude, fmt
from .runner import ROOT, rel, selection_text
from .thesis import COMPONENT_HEADERS, REGION_RANGES, REGIONS

# Analysis variants, in table order: key in results' "variants", label.
VARIANTS = (("boards", "calibrated"), ("unmasked", "calibrated, no masks"), ("ideal", "exact calibration"))
SHORT = {"boards": "", "unmasked": ", no masks", "ideal": ", exact"}


def ratio_to_baseline(results, key, variant, region):
    """Per component: the variant's mean absolute error over the baseline's with the same calibration kind
    (the exact one for "ideal", its boards otherwise); None where either is missing."""
    mine = results["effects"][key]["variants"].get(variant, {}).get(region)
    base = results["effects"]["baseline"]["variants"].get("ideal" if variant == "ideal" else "boards", {}).get(region)
    if not mine or not base or not mine["mae"] or not base["mae"]:
        return (None,) * 6
    return tuple(m / b if m is not None and b else None for m, b in zip(mine["mae"], base["mae"]))


def _effects_section(rep, effects, left_out, results):
    rep.h("The effects")
    rows = []
    for e in effects:
        boards = "its own" if e.rig or e.key == "baseline" else "the baseline's"
        rows.append([f"`{e.key}`", e.what, f"`{rel(ROOT / e.rig) if e.rig else 'scenes/rig.json'}`", f"`{e.path}`",
                     f"`{' '.join(e.render)}`" if e.render else "", boards, f"`{e.dataset.name}`"])
    rep.table(["Effect", "What", "Rig", "Flight path", "More `aar-render render` flags", "Calibration boards",
               "Dataset"], rows, ["---"] * 7)
    sensor = json.loads((ROOT / "scenes/rig-noisy.json").read_text()).get("sensor")
    rep.p(f"The sensor block of `scenes/rig-noisy.json` (docs/rendering.md, \"Sensor model\"): `{json.dumps(sensor)}`. "
          "`rig-all.json`, beside this report, is that rig with the two lenses of `scenes/rig-distorted.json`; "
          "`rig-sensor-noise.json`, `rig-sensor-blur.json` and `rig-sensor-mosaic.json` keep one part of its "
          "sensor each (the other parts through a noise-free sensor: 10^7 e- at radiance 1, no read noise or "
          "fixed pattern, 16-bit ADC).")
    for e in left_out:
        missing = ", ".join(f"`{f}`" for f in results["left_out"][e.key])
        rep.p(f"**Left out: `{e.key}`** ({e.what}): this `aar-render render --help` lists no {missing}.")


def _calibration_section(ctx, rep, results):
    rep.h("Calibration errors against the rig")
    rep.p("`aar-analyze calibrate` on the 12 board pairs rendered through each rig at the same MSAA level "
          "(`calibration_report.json`, `versus_ideal`: against the rig the boards were rendered with). The lens "
          "is estimated (k1 k2 p1 p2) when the rig declares one. The largest ray error is the larger of the two "
          "cameras' largest distance, over the image, between a pixel undistorted with the estimate and with "
          "the rig's own lens: what the calibration gets wrong anywhere in the image, lens included.")
    cals = results["calibrations"]
    rows = [[f"`{k}`", str(c["pairs"]), "yes" if c["distortion"] else "no"]
            + [fmt(c[key], digits) for key, _, digits in CALIBRATION_ERRORS] for k, c in cals.items()]
    rep.table(["Boards of", "Pairs used", "Lens estimated"] + [h for _, h, _ in CALIBRATION_ERRORS], rows,
              ["---", "---:", "---"] + ["---:"] * len(CALIBRATION_ERRORS))
    path = ctx.out / "realism_calibration.png"
    plots.grouped_bars(path, "Calibration error against the rig, per rig (12 boards)", "error (px)", list(cals),
                       [(h, [cals[k][key] for k in cals]) for key, h, _ in CALIBRATION_ERRORS
                        if key in ("rms_px", "epipolar_px", "ray_error_max_px")], logy=True)
    rep.image(path, "RMS re-projection, epipolar and largest ray error of each rig's calibration (log scale)")


def _regions(results):
    present = set()
    for e in results["effects"].values():
        for v in e["variants"].values():
            present.update(v)
    return [g for g in REGIONS if g in present]


def _variant_rows(results, region, cells):
    """Table rows of every effect's analysis variants in `region`: effect (on its first row), variant label, then
    cells(effect key, variant, region result)."""
    rows = []
    for key, e in results["effects"].items():
        first = True
        for variant, label in VARIANTS:
            r = e["variants"].get(variant, {}).get(region)
            if r is None:
                continue
            rows.append([f"`{key}`" if first else "", label] + cells(key, variant, r))
            first = False
    return rows


def _error_cells(results, region):
    def cells(key, variant, r):
        ratios = ratio_to_baseline(results, key, variant, region) if key != "baseline" else (None,) * 6
        mae = r["mae"] or (None,) * 6
        return ([fmt(v) + (f" ({q:.2f})" if q is not None else "") for v, q in zip(mae, ratios)]
                + [f"{r['ok']}/{r['frames']}", str(r["gross"])])
    return cells


def _region_section(ctx, rep, results, region):
    rep.h(f"Region {region} ({REGION_RANGES[region]}): mean absolute error", 3)
    rows = _variant_rows(results, region, _error_cells(results, region))
    rep.table(["Effect", "Analysis"] + list(COMPONENT_HEADERS) + ["Frames ok/all", f"> {results['gross_deg']:g} deg"],
              rows, ["---", "---"] + ["---:"] * 8)
    series = []
    cats = [(key, variant) for key in results["effects"] if key != "baseline" for variant in ("boards", "unmasked")
            if region in results["effects"][key]["variants"].get(variant, {})]
    for i, header in enumerate(COMPONENT_HEADERS):
        series.append((header.split(" ")[0], [ratio_to_baseline(results, k, v, region)[i] for k, v in cats]))
    path = ctx.out / f"realism_ratio_{region}.png"
    plots.grouped_bars(path, f"Region {region}: mean absolute error over the baseline's (calibrated from boards)",
                       "ratio to the baseline (log)", [k + SHORT[v] for k, v in cats], series, logy=True, hline=1.0,
                       rotation=20, figsize=(9, 4.8))
    rep.image(path, f"Region {region}: each effect's mean absolute error per degree of freedom over the "
                    "baseline's, both calibrated from their boards (1 = no change; log scale)")
    worst = max(((q, k + SHORT[v], COMPONENT_HEADERS[i]) for k, v in cats
                 for i, q in enumerate(ratio_to_baseline(results, k, v, region)) if q is not None),
                default=None, key=lambda t: t[0])
    if worst:
        rep.p(f"Largest ratio in region {region}: `{worst[1]}`, {worst[2]}: {worst[0]:.2f} times the baseline's.")


STAGE_HEADERS = ("Disparity mean (px)", "Disparity RMS (px)", "Off receiver (%)", "Off surface (%)",
                 "On propeller blades (%)", "Blades kept (%)", "Points per frame", "Signed X (m)", "Signed pitch (deg)")


def _stage_cells(st):
    if st is None:
        return ["n/a"] * len(STAGE_HEADERS)
    pct = lambda v: "n/a" if v is None else f"{100.0 * v:.1f}"  # noqa: E731
    return [fmt(st["disparity_mean_px"], 4), fmt(st["disparity_rms_px"], 4), pct(st["off_receiver"]),
            pct(st["off_surface"]), pct(st.get("on_propellers")), pct(st.get("propellers_kept")),
            f"{st['points_per_frame']:.0f}", f"{st['signed_x_m']:+.3f}",
            f"{st['signed_pitch_deg']:+.3f}"]


def _stage_section(rep, results, region):
    rep.h(f"Region {region} ({REGION_RANGES[region]}): stage by stage", 3)
    rows = _variant_rows(results, region, lambda key, variant, r: _stage_cells(r.get("stages")))
    rep.table(["Effect", "Analysis"] + list(STAGE_HEADERS), rows, ["---", "---"] + ["---:"] * len(STAGE_HEADERS))


def write(ctx, effects, left_out, results, sel):
    rep = Report(ctx, "Realism: each effect alone and all together (issue 9, item 6)")
    rep.p("Beyond the thesis: its virtual world lacked the lens, the image sensor, the boom, a textured "
          "background, spinning propellers and motion blur (chapter V, 5.4). Each effect is rendered alone on "
          f"the same CONOPS frames ({selection_text(sel)}), at MSAA x{results['msaa']}, then all together, and "
          "analyzed with `aar-analyze run --preset default` (the analyzer's default pipeline), shelled model. "
          "**Calibrated**: with the calibration from the 12 board pairs rendered through the effect's rig (the "
          "lens, sensor and all-together effects; the others do not change the board images and use the "
          "baseline's). **Exact calibration**: with the dataset's `calibration_ideal.yaml`, the imaging alone. "
          "In parentheses: the ratio to the baseline's error with the same kind of calibration. The default "
          "preset masks the boom of a dataset that has one (boom pixels removed from the tanker's own boom angles "
          "and the rig) and the propellers of a dataset whose propellers turn (points on and behind the discs "
          "dropped under the registered pose; docs/analysis.md). **No masks**: those datasets analyzed again with "
          "`--no-mask-boom` and `--no-mask-propellers`. All numbers are in `results.json` beside this report.")
    _effects_section(rep, effects, left_out, results)
    _calibration_section(ctx, rep, results)
    rep.h("Pose error per region")
    rep.p("Mean absolute error (`summary.json`, `mean_abs_error`), with the ratio to the baseline's in "
          f"parentheses. \"> {results['gross_deg']:g} deg\": measured frames whose roll, pitch or yaw error exceeds "
          f"{results['gross_deg']:g} deg (`frames.csv`), the gross failures that can dominate a mean. "
          "Few frames per region make single components noisy: two good calibrations of the same "
          "pinhole images differ by up to 48 % in a component of region C (docs/performance.md, \"Lens "
          "distortion\").")
    for region in _regions(results):
        _region_section(ctx, rep, results, region)
    rep.h("Stage by stage")
    rep.p("Each stage against the depth truth (every dataset is rendered with `--depth`; docs/analysis.md, "
          "\"Measuring the stages\"), over the measured frames of the region: the disparity error of the sensed "
          "points whose pixel is on the receiver (sensed minus true, after the sub-pixel refinement; mean and RMS), "
          "the share of sensed points whose pixel is not on the receiver (halo, background, boom, propeller blur) "
          "and of those off its surface (also the receiver points whose disparity errs by more than 0.5 px), "
          "the sensed points per frame, and the signed mean error of x and pitch: a mean absolute error equal to "
          "the signed one is a bias, not noise. At the range of region C a mean disparity error of -0.02 px "
          "moves the receiver about 5 cm away (x), since z = f b / d. The boom's mask removes disparities, before these "
          "measurements; the propellers' mask acts in the registration, after them: its rows show the cloud before "
          "the mask.")
    for region in _regions(results):
        _stage_section(rep, results, region)
    return conclude(ctx, rep, [r for e in effects for r in e.runs.values()])
