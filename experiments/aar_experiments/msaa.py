"""Experiment 3 (thesis section 4.3 and Appendix B): the effect of MSAA on calibration and pose estimation.

Tables 6-7: the calibration board rendered and calibrated at every MSAA level.
Tables 8-11: the CONOPS path, shelled model, with MSAA, with only the
calibration anti-aliased, and without. Figures 25-32.
"""

from . import plots
from .outputs import group_table, group_table_counts, ok_rows, pairing_of, read_frames, read_json, read_summary
from .registry import register
from .report import COMPARISON_HEADERS, Report, comparison_rows, conclude, error_plots, fmt, ratio
from .runner import analyze, calibrate, render_calib, render_frames, rel, selection_text, sha256_file
from .thesis import MSAA_LEVELS, REGION_RANGES, REGIONS, THESIS

# The three flight-path configurations, in the thesis's words.
LABELS = {"msaa": "MSAA", "calib": "MSAA Calib", "none": "No MSAA"}
# The four Q elements that are not 0: (row, column) and what they hold.
Q_NONZERO = (((0, 3), "Q[0][3] = -cx"), ((1, 3), "Q[1][3] = -cy"), ((2, 3), "Q[2][3] = f"),
             ((3, 2), "Q[3][2] = 1/b"))


def _calibrations(ctx):
    """calib-x<level> rendered and calibrated per MSAA level: {level: folder}, {level: calibration_report.json}."""
    cal = {}
    reports = {}
    for level in MSAA_LEVELS:
        ds = ctx.dataset(f"calib-x{level}")
        render_calib(ctx, ds, level)
        cal[level] = calibrate(ctx, ds, ctx.out / "calibrations" / f"x{level}")
        reports[level] = read_json(cal[level] / "calibration_report.json")
    return cal, reports


def _flight_runs(ctx, cal, sel):
    """The CONOPS path at x1 and x16, shelled model: {configuration: run folder}, and the two datasets."""
    ds1 = ctx.dataset("conops-x1")
    ds16 = ctx.dataset("conops-x16")
    render_calib(ctx, ds1, 1)
    render_frames(ctx, ds1, 1, "flightpaths/conops.csv", sel)
    render_calib(ctx, ds16, 16)
    render_frames(ctx, ds16, 16, "flightpaths/conops.csv", sel)
    runs = {
        "none": analyze(ctx, "conops-x1-shelled", ds1, "shelled", sel),
        "calib": analyze(ctx, "conops-x1-shelled-calib-x16", ds1, "shelled", sel,
                         calibration=cal[16] / "calibration.yaml"),
        "msaa": analyze(ctx, "conops-x16-shelled", ds16, "shelled", sel),
    }
    return runs, ds1, ds16


def _table6(rep, reports):
    rep.h("Table 6: calibration error per MSAA level")
    rep.p("RMS re-projection error: `stereoCalibrate`'s return value; epipolar error: mean distance of each "
          "corner to its partner's epipolar line (docs/analysis.md; OpenCV's `stereo_calib` sample prints twice "
          "this). Change vs x1 (%) = 100 (level - x1) / x1, negative = smaller error than x1.")
    rows = []
    for key, label in (("rms_reprojection_px", "rms"), ("epipolar_error_px", "epipolar")):
        name = "RMS re-projection (px)" if label == "rms" else "Epipolar constraint (px)"
        ours = [reports[lv][key] for lv in MSAA_LEVELS]
        th = [THESIS["table6"][label][lv] for lv in MSAA_LEVELS]
        rows.append([name, "ours"] + [fmt(v, 6) for v in ours])
        rows.append(["", "thesis"] + [fmt(v, 6) for v in th])
        rows.append(["", "ours/thesis"] + [fmt(ratio(a, b), 3) for a, b in zip(ours, th)])
        rows.append(["", "change vs x1 (%), ours"] + [fmt(100.0 * (v - ours[0]) / ours[0], 1) for v in ours])
        rows.append(["", "change vs x1 (%), thesis"] + [fmt(100.0 * (v - th[0]) / th[0], 1) for v in th])
    rep.table(["Type of error", "Source"] + [("No MSAA (x1)" if lv == 1 else f"MSAAx{lv}") for lv in MSAA_LEVELS],
              rows)
    rows = []
    for lv in MSAA_LEVELS:
        r = reports[lv]
        v = r["versus_ideal"]
        rows.append([f"x{lv}", f"{r['used_pairs']}", fmt(r.get("left_rms_px"), 4), fmt(r.get("right_rms_px"), 4),
                     fmt(v["focal_error_percent"], 4), fmt(v["baseline_error_percent"], 4),
                     fmt(v["left_principal_point_error_px"], 3), fmt(v["rotation_error_deg"], 4)])
    rep.p("Further calibration results against the true rig (ours; `calibration_report.json`):")
    rep.table(["MSAA", "Pairs used", "Left RMS (px)", "Right RMS (px)", "Focal error (%)", "Baseline error (%)",
               "Left principal point error (px)", "Rotation error (deg)"], rows)


def _table7(rep, reports):
    rep.h("Table 7: element-wise percent error of Q against the ideal Q")
    rep.p("`100 |q - q_ideal| / |q_ideal|` (0 where the ideal element is 0), from `versus_ideal.q_percent_error`. "
          "Q = [[1,0,0,-cx],[0,1,0,-cy],[0,0,0,f],[0,0,1/b,0]] after rectification, so the four non-zero "
          "elements are the rectified principal point (cx, cy), the focal length and the inverse baseline. "
          "Every other element is 0 in both sources. Note: stereoRectify (CALIB_ZERO_DISPARITY, alpha -1) moves "
          "the rectified principal point when the two estimated cameras differ, so Q[0][3] measures the "
          "rectification as much as the intrinsics.")
    rows = []
    for (i, j), name in Q_NONZERO:
        row = [name]
        for lv in (1, 16):
            o = reports[lv]["versus_ideal"]["q_percent_error"][i][j]
            t = THESIS["table7"][lv][(i, j)]
            row += [fmt(o, 3), fmt(t, 3), fmt(ratio(o, t), 2)]
        rows.append(row)
    nonzero = [ij for ij, _ in Q_NONZERO]
    others = max(reports[lv]["versus_ideal"]["q_percent_error"][i][j] for lv in (1, 16) for i in range(4)
                 for j in range(4) if (i, j) not in nonzero)
    rep.table(["Element", "No MSAA Q ours (%)", "thesis (%)", "ours/thesis", "MSAAx16 Q ours (%)", "thesis (%)",
               "ours/thesis"], rows)
    rep.p(f"Largest percent error of any other element (ours, x1 and x16): {fmt(others, 6)}.")
    for lv in (1, 16):
        q = reports[lv]["versus_ideal"]["q_percent_error"]
        rep.p(f"Full 4x4 percent-error matrix, x{lv} (ours):")
        rep.table(["", "col 0", "col 1", "col 2", "col 3"],
                  [[f"row {i}"] + [fmt(q[i][j], 4) for j in range(4)] for i in range(4)])


def _calibration_crosscheck(rep, runs, cal):
    """The conops datasets' own calibrations equal the separate calib-x1 / calib-x16 ones."""
    rows = []
    for key, lv in (("none", 1), ("msaa", 16)):
        a = sha256_file(runs[key] / "calibration.yaml")
        b = sha256_file(cal[lv] / "calibration.yaml")
        rows.append([LABELS[key], f"calib-x{lv}", "identical" if a == b else "DIFFERENT", f"`{a[:16]}`",
                     f"`{b[:16]}`"])
    rows.append([LABELS["calib"], "calib-x16 (via --calibration)",
                 "identical" if sha256_file(runs["calib"] / "calibration.yaml")
                 == sha256_file(cal[16] / "calibration.yaml") else "DIFFERENT", "", ""])
    rep.p("Calibration used by each flight-path run against the stand-alone calibration of the same MSAA level "
          "(SHA-256 of calibration.yaml; identical board images give identical calibrations):")
    rep.table(["Flight run", "Stand-alone calibration", "calibration.yaml", "run (SHA-256 prefix)",
               "stand-alone (SHA-256 prefix)"], rows, ["---"] * 5)


def _flight_tables(rep, runs, summaries, sel, ds1, ds16):
    """Tables 8-11."""
    rep.h("Flight path with and without MSAA (Tables 8-11)")
    rep.p(f"CONOPS path, shelled model, 30 ICP iterations, `{pairing_of(runs['none'])}` ICP pairing (the "
          "analyzer's default), " + selection_text(sel) + ". "
          f"**No MSAA**: imagery x1 (`{rel(ds1)}`) and its own x1 calibration. **MSAA Calib** (the "
          "thesis's \"partial MSAA\"): imagery x1 with `--calibration` from the x16 calibration. **MSAA**: imagery "
          f"x16 (`{rel(ds16)}`) and its own x16 calibration. The thesis reports region A orientation "
          "here (unlike Table 4). Difference (%) as in the thesis: Table 8 = 100 (No MSAA - MSAA Calib) / No MSAA, "
          "Table 9 = 100 (MSAA Calib - MSAA) / MSAA Calib, Table 10 = 100 (No MSAA - MSAA) / No MSAA.")
    km = {LABELS[k]: (summaries[k], "shelled") for k in ("msaa", "calib", "none")}
    mean = group_table(km, REGIONS, "mean_abs_error")
    rms = group_table(km, REGIONS, "rms_error")
    counts = group_table_counts(km, REGIONS)
    th_mean = {g: {LABELS[k]: THESIS["mean_abs"][k][g] for k in LABELS} for g in REGIONS}
    th_rms = {g: {LABELS[k]: THESIS["table11"][k][g] for k in LABELS} for g in REGIONS}
    for title, pair, tdiff in (
            ("Table 8: mean absolute error, MSAA calibration only versus no MSAA", ("No MSAA", "MSAA Calib"),
             THESIS["table8_diff"]),
            ("Table 9: mean absolute error, MSAA versus MSAA calibration only", ("MSAA Calib", "MSAA"),
             THESIS["table9_diff"]),
            ("Table 10 (Appendix B): mean absolute error, MSAA versus no MSAA", ("No MSAA", "MSAA"),
             THESIS["table10_diff"])):
        rep.h(title, 3)
        rep.table(COMPARISON_HEADERS, comparison_rows(
            REGIONS, (pair[1], pair[0]), mean, th_mean, diff=(pair[0], pair[1], tdiff), counts=counts,
            group_label=lambda g: f"Region {g} ({REGION_RANGES[g]})"))
    rep.h("Table 11 (Appendix B): RMS error, MSAA, MSAA calibration only and no MSAA", 3)
    rep.p("The thesis's \"MSAA\" rows of Table 11 repeat its Table 9 mean absolute values digit for digit, so "
          "the ratio against them is likely against a mean, not an RMS.")
    rep.table(COMPARISON_HEADERS, comparison_rows(
        REGIONS, ("MSAA", "MSAA Calib", "No MSAA"), rms, th_rms, counts=counts,
        group_label=lambda g: f"Region {g} ({REGION_RANGES[g]})"))


def _figures(ctx, rep, reports, frames):
    """Figures 25-32."""
    rep.h("Figures")
    path = ctx.out / "msaa_calibration_error.png"
    plots.grouped_bars(path, "Calibration error per MSAA level (cf. thesis Table 6)", "error (px)",
                       [f"x{lv}" for lv in MSAA_LEVELS],
                       [("RMS re-projection, ours", [reports[lv]["rms_reprojection_px"] for lv in MSAA_LEVELS]),
                        ("epipolar, ours", [reports[lv]["epipolar_error_px"] for lv in MSAA_LEVELS]),
                        ("RMS re-projection, thesis", [THESIS["table6"]["rms"][lv] for lv in MSAA_LEVELS]),
                        ("epipolar, thesis", [THESIS["table6"]["epipolar"][lv] for lv in MSAA_LEVELS])])
    rep.image(path, "RMS re-projection and epipolar error per MSAA level, ours and the thesis's (Table 6)")
    for key, figs, what in (("none", (26, 27), "no MSAA (imagery x1, calibration x1)"),
                            ("calib", (28, 29), "MSAA calibration only (imagery x1, calibration x16)"),
                            ("msaa", (31, 32), "MSAA (imagery x16, calibration x16)")):
        for path, cap in error_plots(ctx, frames[key], f"msaa_{key}", f"CONOPS path, {what}", figs, "regions"):
            rep.image(path, cap)
    path = ctx.out / "msaa_y_error.png"
    series = []
    for key in ("none", "calib", "msaa"):
        ok = ok_rows(frames[key])
        series.append((LABELS[key], [r["range_m"] for r in ok], [r["err_y_m"] for r in ok]))
    plots.scatter_vs_range(path, "Y error on the CONOPS path, the three MSAA configurations (cf. thesis Figure 30)",
                           "Y error (m)", series, guides="regions")
    rep.image(path, "Y (lateral) error versus range for no MSAA, MSAA calibration only and MSAA "
                    "(cf. thesis Figure 30, which shows the Y error as point clouds)")


@register("msaa", order=3,
          help="thesis Experiment 3: MSAA x1-x32 calibration and the CONOPS path with/without MSAA "
               "(Tables 6-11, Figures 25-32)")
def run(ctx):
    cal, reports = _calibrations(ctx)
    sel = ctx.sel["conops"]
    runs, ds1, ds16 = _flight_runs(ctx, cal, sel)
    summaries = {k: read_summary(v) for k, v in runs.items()}
    frames = {k: read_frames(v) for k, v in runs.items()}

    rep = Report(ctx, "Experiment 3: effect of MSAA on calibration and pose estimation")
    rep.p("Thesis section 4.3 and Appendix B (Tables 6-11, Figures 25-32). The calibration board is rendered "
          "at its 12 poses (`aar-render calib`, the thesis used 10) at MSAA x1, x4, x8, x16 and x32 into separate "
          "datasets and calibrated with `aar-analyze calibrate` (OpenCV: chessboard corners + cornerSubPix, "
          "calibrateCamera, stereoCalibrate, stereoRectify; distortion fixed at zero, the renderer has none). "
          "x1 is a single sample per pixel (the thesis's \"No MSAA\"); x8, x16 and x32 are composed of jittered "
          "passes of the device's native x4 (see the manifests).")
    _table6(rep, reports)
    _table7(rep, reports)
    _calibration_crosscheck(rep, runs, cal)
    _flight_tables(rep, runs, summaries, sel, ds1, ds16)
    _figures(ctx, rep, reports, frames)
    return conclude(ctx, rep, [runs["none"], runs["calib"], runs["msaa"]])
