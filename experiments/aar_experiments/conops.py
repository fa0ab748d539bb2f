"""Experiment 2 (thesis section 4.2): the CONOPS flight path, shelled versus full reference model.

Tables 4-5, Figures 20-24: flightpaths/conops.csv (609 samples, 175 m to the
contact position at 32 m) in the thesis's regions A, B and C.

Two geometries (--geometry): `default`, scenes/rig.json with conops.csv,
where the receiver is always entirely in view; and `thesis` (issue 9, item 1),
scenes/rig-thesis.json (cameras pitched 41 deg down) with conops-level.csv
(the same approach, level at the contact height from 37 m), where the
receiver's T-tail leaves the top of the images at about 39 m and is back in
view inside region C, as in thesis Figure 24. The thesis geometry's report
adds where the tail leaves and returns, the in-view fraction per frame, and
the errors of the frames with the tail out against their in-view neighbours
and against the same frames on the default geometry.
"""

import math
from dataclasses import dataclass

from . import plots
from .outputs import ok_rows, read_frames, read_json, sidecar
from .registry import register
from .report import Report, conclude, fmt, mean_abs
from .runner import analyze, render_calib, render_frames, selected_frames, selection_text
from .shelled_vs_full import (both_pairings, dump_option, frames_per_region, model_error_plots, model_tables,
                              region_overlays, render_and_analyze)
from .thesis import COMPONENT_HEADERS, COMPONENTS, REGION_RANGES, REGIONS


@dataclass(frozen=True)
class Geometry:
    rig: object         # rig JSON passed to aar-render (None: its default, scenes/rig.json)
    flight_path: str
    dataset: str        # dataset name on the flat sky (other backgrounds append -BACKGROUND)
    selection: str      # key of runner.SELECTIONS


GEOMETRIES = {
    "default": Geometry(None, "flightpaths/conops.csv", "conops-x16", "conops"),
    "thesis": Geometry("scenes/rig-thesis.json", "flightpaths/conops-level.csv", "conops-thesis-x16",
                       "conops_thesis"),
}


def dataset_name(geometry, background):
    return GEOMETRIES[geometry].dataset + ("" if background == "flat" else f"-{background}")

# Where the thesis saw the receiver's tail leave the view (Figure 24).
TAIL_BAND_M = (38.0, 42.0)


def _tables(rep, summaries, note):
    """Tables 4-5 (thesis layout) from {model: summary.json}."""
    model_tables(rep, summaries, note, REGIONS, lambda g: f"Region {g} ({REGION_RANGES[g]})",
                 (("Table 4: mean absolute 6DOF error per region", "mean_abs_error", "table4"),
                  ("Table 5: RMS 6DOF error per region", "rms_error", "table5")))


def _registration_details(rep, res):
    rep.h(f"Registration details per region (ours, {res.pairing})")
    rows = []
    for g in REGIONS:
        for m in ("full", "shelled"):
            s = res.summaries[m]["models"][m][g]
            t = res.summaries[m]["timing"][m][g]
            rows.append([g, m, f"{s['ok']}/{s['frames']}", fmt(s.get("sensed_points_mean"), 0),
                         fmt(s.get("icp_iterations_mean"), 1), fmt(s.get("icp_rmse_m_mean"), 3),
                         fmt(t["icp_ms_mean"], 1)])
    rep.table(["Region", "Model", "Frames ok/all", "Sensed points (mean)", "ICP iterations (mean)",
               "ICP RMSE (m, mean)", "ICP time (ms, mean; machine-dependent)"], rows)


def _partial_visibility(rep, res):
    """Partial visibility (thesis Figure 24: the tail leaves the view at 38-42 m); returns the sidecars'
    (frame, range, in_view left, in_view right) per analyzed frame."""
    rep.h("Partial visibility (cf. thesis Figure 24)")
    vis = []
    for r in res.frames["shelled"]:
        sc = sidecar(res.dataset, r["frame"])
        vis.append((r["frame"], r["range_m"], sc["in_view"]["left"], sc["in_view"]["right"]))
    partial = [v for v in vis if min(v[2], v[3]) < 1.0]
    min_left = min(v[2] for v in vis)
    min_right = min(v[3] for v in vis)
    if partial:
        lo = min(v[1] for v in partial)
        hi = max(v[1] for v in partial)
        rep.p(f"{len(partial)} of the {len(vis)} analyzed frames have part of the receiver outside an image "
              f"(sidecar `in_view` < 1), at {lo:.2f}-{hi:.2f} m; smallest fractions: left {min_left:.4f}, "
              f"right {min_right:.4f}.")
    else:
        rep.p(f"In our geometry the receiver is never partly out of view on the CONOPS path: the sidecars of all "
              f"{len(vis)} analyzed frames report `in_view` = {min_left:.4f} (left, smallest) and "
              f"{min_right:.4f} (right, smallest), i.e. every vertex of the receiver model projects inside both "
              "images at every range, as the flight-path generator predicts (flightpaths/README.md: the "
              "contact position lies on the optical axis of cameras pitched 30 deg down, and the receiver's box "
              "keeps at least 114 px of margin). The thesis's tail loss at 38-42 m therefore has no counterpart "
              "here; the table compares the 38-42 m band, where the thesis saw it, with the rest of region B.")
    band = TAIL_BAND_M
    rows = []
    pf = {v[0] for v in partial}
    for m in ("full", "shelled"):
        ok = ok_rows(res.frames[m])
        subsets = [(f"{band[0]:.0f}-{band[1]:.0f} m", [r for r in ok if band[0] <= r["range_m"] < band[1]]),
                   ("rest of region B", [r for r in ok if r["region"] == "B"
                                         and not band[0] <= r["range_m"] < band[1]])]
        if partial:
            subsets.append(("partly out of view", [r for r in ok if r["frame"] in pf]))
        for label, sub in subsets:
            rows.append([m, label, str(len(sub))] + [fmt(mean_abs([r["err_" + c] for r in sub]), 3)
                                                     for c in COMPONENTS])
    rep.table(["Model", "Frames", "Count"] + [f"mean abs {h}" for h in COMPONENT_HEADERS], rows)
    return vis


PRESETS = (("thesis preset (strict shell)", "thesis"), ("default preset", "default"))


def _presets(ctx, rep, res):
    """The estimator's presets beside the published pipeline, on the same frames; returns their run folders."""
    rep.h("Estimator presets side by side (shelled model)")
    rep.p("`aar-analyze run --preset thesis` (the thesis's pipeline with the strict shell) and `--preset default` "
          "(halo removal, StereoBM rounding correction, robust noise-weighted point-to-plane ICP; "
          "docs/analysis.md) against the pipeline the tables above use (thesis preset with the first version's "
          "loose shell, sensed-to-model pairing and a 1/32 px offset). Mean absolute error; every frame counted "
          "in `Frames ok/all`.")
    cases = [("published pipeline", res.summaries["shelled"])]
    dirs = []
    for label, preset in PRESETS:
        d = analyze(ctx, f"{res.dataset.name}-shelled-preset-{preset}", res.dataset, "shelled", res.selection,
                    extra=("--preset", preset))
        dirs.append(d)
        cases.append((label, read_json(d / "summary.json")))
    rows = []
    for g in REGIONS:
        for label, summary in cases:
            st = summary["models"]["shelled"][g]
            err = st.get("mean_abs_error") or {}
            rows.append([g, label, f"{st['ok']}/{st['frames']}"] + [fmt(err.get(c), 3) for c in COMPONENTS])
    rep.table(["Region", "Pipeline", "Frames ok/all"] + [f"mean abs {h}" for h in COMPONENT_HEADERS], rows)
    return dirs


def _figures(ctx, rep, res, vis, shade=(TAIL_BAND_M[0], TAIL_BAND_M[1], "thesis: tail out of view")):
    """Figures 20-24."""
    rep.h("Figures")
    model_error_plots(ctx, rep, res, "conops", (("shelled", (20, 21)), ("full", (22, 23))), "CONOPS path",
                      "regions")
    path = ctx.out / "conops_visibility.png"
    ok = ok_rows(res.frames["shelled"])
    norm = [math.sqrt(r["err_x_m"] ** 2 + r["err_y_m"] ** 2 + r["err_z_m"] ** 2) for r in ok]
    plots.panels_vs_range(
        path, "Receiver visibility and position error on the CONOPS path (cf. thesis Figure 24)",
        [("fraction of receiver\nvertices in view (sidecar)",
          [("left camera", [v[1] for v in vis], [v[2] for v in vis]),
           ("right camera", [v[1] for v in vis], [v[3] for v in vis])], (0.0, 1.08)),
         ("position error norm (m)\nshelled model", [("|estimate - truth|", [r["range_m"] for r in ok], norm)])],
        guides="regions", shade=shade)
    rep.image(path, "Visible fraction of the receiver (sidecar in_view) and shelled position error versus range "
                    "(cf. thesis Figure 24)")
    region_overlays(ctx, rep, res, "conops")


def _cloud_truth(rep, cases):
    """The sensed cloud against depth truth per region (datasets with --depth): {label: frames.csv rows}."""
    rep.h("The sensed cloud against depth truth (shelled model)")
    rep.p("Sums over the analyzed frames of `frames.csv`'s `truth_*` columns (docs/analysis.md, \"The cloud "
          "against depth truth\"): sensed points whose pixel is not the receiver in the truth mask (halo, "
          "background), points off the surface (those, plus receiver points more than 0.5 px of disparity "
          "off), and the RMS disparity error of the points on the receiver.")
    rows = []
    for g in REGIONS:
        for label, frames in cases:
            sub = [r for r in frames if r["region"] == g and r.get("truth_points")]
            points = sum(r["truth_points"] for r in sub)
            on = sum(r["truth_points"] - r["truth_off_receiver"] for r in sub)
            sq = sum(r["truth_error_squared_sum_px2"] for r in sub)
            rows.append([g, label, str(int(points)),
                         fmt(100.0 * sum(r["truth_off_receiver"] for r in sub) / points if points else None, 2),
                         fmt(100.0 * sum(r["truth_off_surface"] for r in sub) / points if points else None, 2),
                         fmt(math.sqrt(sq / on) if on else None, 3)])
    rep.table(["Region", "Pipeline", "Points", "Off receiver (%)", "Off surface (%)",
               "RMS disparity error on the receiver (px)"], rows)


# ---------------------------------------------------------------------------
# The thesis geometry (issue 9, item 1): where the tail leaves the view
# ---------------------------------------------------------------------------

# The pipelines compared frame by frame (shelled model): label, how to find its frames.csv rows.
TAIL_PIPELINES = ("published pipeline", "thesis preset", "default preset")
DOF_LABELS = ("x (m)", "y (m)", "z (m)", "roll (deg)", "pitch (deg)", "yaw (deg)")


def _in_view(dataset, frames):
    """{frame: (range_m, region, in_view left, in_view right)} from the sidecars."""
    out = {}
    for f in frames:
        sc = sidecar(dataset, f)
        out[f] = (sc["range_m"], sc["region"], sc["in_view"]["left"], sc["in_view"]["right"])
    return out


def _least_in_view_overlay(dataset, selection):
    """more_overlays for render_and_analyze: the selected frame with the least of the receiver in view."""
    count = read_json(dataset / "manifest.json")["frames"]["count"]
    vis = _in_view(dataset, selected_frames(selection, count))
    frame = min(vis, key=lambda f: (min(vis[f][2], vis[f][3]), f))
    return {"tail out of view": frame} if min(vis[frame][2], vis[frame][3]) < 1.0 else {}


def _control(ctx, selection, render_extra):
    """The same frames on the default geometry (rig.json, conops.csv: same ranges and attitudes, receiver
    always in view), analyzed as Experiment 2 analyzes it, so that `all` reuses those analyses: {pipeline label:
    run folder}, and the dataset."""
    ds = ctx.dataset(dataset_name("default", ctx.background))
    render_calib(ctx, ds, 16)
    render_frames(ctx, ds, 16, GEOMETRIES["default"].flight_path, selection, render_extra)
    runs = {"published pipeline": analyze(ctx, f"{ds.name}-shelled", ds, "shelled", selection,
                                          extra=dump_option(frames_per_region(ds, selection)))}
    for label, preset in PRESETS:
        runs[label.split(" (")[0]] = analyze(ctx, f"{ds.name}-shelled-preset-{preset}", ds, "shelled", selection,
                                             extra=("--preset", preset))
    return runs, ds


def _stretches(frames, vis):
    """Runs of consecutive selected frames with part of the receiver out of view: [(first, last) index into
    `frames`]."""
    out = []
    start = None
    for k, f in enumerate(frames):
        partial = min(vis[f][2], vis[f][3]) < 1.0
        if partial and start is None:
            start = k
        if not partial and start is not None:
            out.append((start, k - 1))
            start = None
    if start is not None:
        out.append((start, len(frames) - 1))
    return out


def _edge_text(dataset, frame, camera):
    """Where the receiver touches the border of a flat-sky image: its pixels (those not of the sky's colour,
    taken from a corner) on the top and bottom rows and the left and right columns."""
    import matplotlib.image as mpimg
    import numpy as np

    image = mpimg.imread(dataset / "frames" / f"{frame:06d}_{camera}.png")[:, :, :3]
    receiver = np.abs(image - image[-1, 0]).sum(axis=2) > 0.02
    edges = {"top row": receiver[0], "bottom row": receiver[-1], "left column": receiver[:, 0],
             "right column": receiver[:, -1]}
    parts = []
    for name, line in edges.items():
        hits = np.nonzero(line)[0]
        if len(hits):
            parts.append(f"{len(hits)} receiver pixels on the {name} ({'columns' if 'row' in name else 'rows'} "
                         f"{hits[0]}-{hits[-1]})")
    return ", ".join(parts) + ", none on the other edges" if parts else "no receiver pixel on any edge"


def _stats(rows, frames):
    """(ok count, all count, mean abs error per DOF) over `frames` of frames.csv rows {frame: row}."""
    sub = [rows[f] for f in frames if f in rows]
    ok = ok_rows(sub)
    return len(ok), len(sub), [mean_abs([r["err_" + c] for r in ok]) for c in COMPONENTS]


def _span(frames, vis):
    return (f"{frames[0]}-{frames[-1]} ({vis[frames[0]][0]:.2f}-{vis[frames[-1]][0]:.2f} m, "
            + "/".join(sorted({vis[f][1] for f in frames})) + ")") if frames else "none"


def _tail(ctx, rep, res, preset_dirs, control):
    """Where the tail leaves and returns, the in-view fraction per frame, the errors with the tail out against
    the neighbouring frames and against the same frames on the default geometry; figures. Returns the
    visibility list _figures takes and the band to shade."""
    control_runs, control_ds = control
    frames = [r["frame"] for r in res.frames["shelled"]]
    vis = _in_view(res.dataset, frames)
    control_vis = _in_view(control_ds, frames)
    rows = {"published pipeline": {r["frame"]: r for r in res.frames["shelled"]}}
    for (label, _), d in zip(PRESETS, preset_dirs):
        rows[label.split(" (")[0]] = {r["frame"]: r for r in read_frames(d)}
    crows = {label: {r["frame"]: r for r in read_frames(d)} for label, d in control_runs.items()}
    drange = max(abs(vis[f][0] - control_vis[f][0]) for f in frames)

    rep.h("Where the tail leaves the view (thesis geometry; cf. thesis Figure 24)")
    rep.p("`in_view` in each frame's sidecar is the fraction of the receiver model's 27,714 vertices that project "
          "inside the image (docs/dataset-format.md), for the left and the right camera. On this rig the receiver's "
          "top edge, the T-tail, is near the top of the images, and the level final approach at the contact height "
          "takes it out of the frame (flightpaths/README.md, `conops-level.csv`). Control: the same frame indices "
          f"of `{GEOMETRIES['default'].flight_path}` on `scenes/rig.json` (`{control_ds.name}`), the same approach "
          f"(range within {1000 * drange:.1f} mm of this path's at every analyzed frame, the same attitude) seen "
          "from 30 deg down with the receiver on the optical axis, entirely in view (smallest `in_view` there: "
          f"{min(min(v[2], v[3]) for v in control_vis.values()):.4f}). It differs from the thesis geometry in "
          "the view angle and the image position as well, so the neighbouring frames on the same rig are the "
          "closer comparison.")
    stretches = _stretches(frames, vis)
    if not stretches:
        rep.p(f"None of the {len(frames)} analyzed frames ({selection_text(res.selection)}) has part of the "
              "receiver out of view; nothing to compare.")
        return [(f, vis[f][0], vis[f][2], vis[f][3]) for f in frames], None
    trows = []
    for a, b in stretches:
        out = frames[a:b + 1]
        least = min(out, key=lambda f: (min(vis[f][2], vis[f][3]), f))
        before = frames[a - 1] if a > 0 else None
        after = frames[b + 1] if b + 1 < len(frames) else None
        trows.append([
            f"{before} ({vis[before][0]:.2f} m, {vis[before][1]})" if before is not None else "not analyzed",
            f"{out[0]} ({vis[out[0]][0]:.2f} m, {vis[out[0]][1]})",
            f"{out[-1]} ({vis[out[-1]][0]:.2f} m, {vis[out[-1]][1]})",
            f"{after} ({vis[after][0]:.2f} m, {vis[after][1]})" if after is not None else "not analyzed",
            str(len(out)),
            f"{vis[least][2]:.4f} / {vis[least][3]:.4f} (frame {least}, {vis[least][0]:.2f} m)",
            f"{mean_abs([1.0 - vis[f][2] for f in out]):.4f} / {mean_abs([1.0 - vis[f][3] for f in out]):.4f}"])
    rep.table(["Last frame in view", "First frame out", "Last frame out", "First frame back in view",
               "Frames out", "Smallest in_view left / right", "Mean fraction out of view, left / right"], trows)
    if ctx.background == "flat":
        least = min(frames, key=lambda f: (min(vis[f][2], vis[f][3]), f))
        rep.p(f"Which edge: in frame {least}, " + "; ".join(
            f"the {cam} image has {_edge_text(res.dataset, least, cam)}" for cam in ("left", "right"))
            + " (pixels that differ from the flat sky's colour in the image's outermost rows and columns).")
    same = all(vis[f][2] == vis[f][3] for f in frames)
    rep.p(f"{sum(b - a + 1 for a, b in stretches)} of the {len(frames)} analyzed frames have part of the receiver "
          "out of view" + (" (left and right equal in every frame)." if same else "."))

    # Per frame, with the tail out.
    rep.h("Per frame with the tail out: in-view fraction and error (default preset, shelled)", 3)
    prow = []
    for a, b in stretches:
        for f in frames[a:b + 1]:
            r = rows["default preset"].get(f)
            status = r["status"] if r else "not analyzed"
            errs = [fmt(r["err_" + c], 3) if r and r["status"] == "ok" else "n/a" for c in COMPONENTS]
            prow.append([str(f), f"{vis[f][0]:.2f}", vis[f][1], f"{vis[f][2]:.4f}", f"{vis[f][3]:.4f}"] + errs
                        + [status])
    rep.table(["Frame", "Range (m)", "Region", "in_view left", "in_view right"]
              + [f"err {h}" for h in DOF_LABELS] + ["Status"], prow)

    # Tail out against its neighbours and against the default geometry.
    rep.h("Errors with the tail out against the neighbouring frames in view", 3)
    a, b = max(stretches, key=lambda s: s[1] - s[0])
    out = frames[a:b + 1]
    k = len(out)
    before = [f for f in frames[max(0, a - k):a] if min(vis[f][2], vis[f][3]) >= 1.0]
    after = [f for f in frames[b + 1:b + 1 + k] if min(vis[f][2], vis[f][3]) >= 1.0]
    rep.p(f"Mean absolute error (shelled model) over the {k} analyzed frames with the tail out and over up to as "
          f"many analyzed frames in view on either side (before: {_span(before, vis)}; after: "
          f"{_span(after, vis)}), on this geometry and on the same frames of the default geometry. "
          "\"out / neighbours\" divides the thesis geometry's tail-out error by its error over the before and "
          "after frames together. Published pipeline: `--preset thesis --shell loose --disparity-offset 0.03125 "
          "--correspondence sensed_to_model`, as in the tables above.")
    nrows = []
    for label in TAIL_PIPELINES:
        pooled = None
        tail = None
        for wname, wframes in (("before (in view)", before), ("tail out", out), ("after (in view)", after)):
            for rig, rr in (("thesis", rows[label]), ("default (control)", crows[label])):
                n_ok, n_all, errs = _stats(rr, wframes)
                nrows.append([label if wname.startswith("before") and rig == "thesis" else "", wname, rig,
                              f"{n_ok}/{n_all}"] + [fmt(e, 3) for e in errs])
                if rig == "thesis" and wname == "tail out":
                    tail = errs
        pooled = _stats(rows[label], before + after)[2]
        nrows.append(["", "out / neighbours", "thesis", ""]
                     + [fmt(t / n if t is not None and n else None, 2) for t, n in zip(tail, pooled)])
    rep.table(["Pipeline", "Frames", "Geometry", "ok/all"] + [f"mean abs {h}" for h in COMPONENT_HEADERS], nrows)
    _tail_figures(ctx, rep, res, frames, vis, rows, crows, (before, out, after))
    return ([(f, vis[f][0], vis[f][2], vis[f][3]) for f in frames],
            (vis[out[-1]][0], vis[out[0]][0], "tail out of view (measured)"))


def _geometries(rep, res, preset_dirs, control):
    """Per region, the thesis geometry against the default geometry on the same frames."""
    control_runs, _ = control
    rep.h("The two geometries per region (shelled model)")
    rep.p("Mean absolute error per region on the thesis geometry and on the same frames of the default geometry "
          "(the control above). Regions B and C include the frames with the tail out.")
    runs = {"published pipeline": res.runs["shelled"]}
    for (label, _), d in zip(PRESETS, preset_dirs):
        runs[label.split(" (")[0]] = d
    rows = []
    for g in REGIONS:
        for label in TAIL_PIPELINES:
            for rig, d in (("thesis", runs[label]), ("default", control_runs[label])):
                st = read_json(d / "summary.json")["models"]["shelled"][g]
                err = st.get("mean_abs_error") or {}
                rows.append([g if label == TAIL_PIPELINES[0] and rig == "thesis" else "",
                             label if rig == "thesis" else "", rig, f"{st['ok']}/{st['frames']}"]
                            + [fmt(err.get(c), 3) for c in COMPONENTS])
    rep.table(["Region", "Pipeline", "Geometry", "Frames ok/all"] + [f"mean abs {h}" for h in COMPONENT_HEADERS],
              rows)


def _region_start(dataset, frame):
    """The first frame of the region of `frame` (walking back over rendered frames), or None when `frame` is
    None or the frame before the region's first is not rendered (so the boundary is unknown)."""
    if frame is None:
        return None
    region = sidecar(dataset, frame)["region"]
    while frame > 0:
        path = dataset / "frames" / f"{frame - 1:06d}.json"
        if not path.is_file():
            return None
        if read_json(path)["region"] != region:
            return frame
        frame -= 1
    return None


def _tail_figures(ctx, rep, res, frames, vis, rows, crows, windows):
    """The in-view fraction and the error per DOF frame by frame, over regions B and C (by frame index) and
    around the tail-out stretch (by range)."""
    before, out, after = windows
    series_of = (("thesis geometry, default preset", rows["default preset"], "tab:blue"),
                 ("thesis geometry, published pipeline", rows["published pipeline"], "tab:orange"),
                 ("thesis geometry, thesis preset", rows["thesis preset"], "tab:red"),
                 ("default geometry (control), default preset", crows["default preset"], "0.55"))

    def panels(xof, keep):
        sel = [f for f in frames if keep(f)]
        p = [("fraction of receiver\nvertices in view",
              [("left camera", [xof(f) for f in sel], [vis[f][2] for f in sel], "tab:green"),
               ("right camera", [xof(f) for f in sel], [vis[f][3] for f in sel], "tab:purple")], (-0.02, 1.06))]
        for c, lab in zip(COMPONENTS, DOF_LABELS):
            series = []
            for label, rr, color in series_of:
                ok = [f for f in sel if f in rr and rr[f]["status"] == "ok"]
                series.append((label, [xof(f) for f in ok], [rr[f]["err_" + c] for f in ok], color))
            p.append((f"error {lab}", series))
        return p

    bc = [f for f in frames if vis[f][1] in ("B", "C")]
    if bc:
        edges = []
        for g in ("B", "C"):
            first = _region_start(res.dataset, next((f for f in frames if vis[f][1] == g), None))
            if first is not None:
                edges.append((first - 0.5, f"region {g} from frame {first} "
                                           f"({sidecar(res.dataset, first)['range_m']:.1f} m)"))
        path = ctx.out / "conops_thesis_by_frame.png"
        plots.panels_vs_x(path, "Thesis geometry: in-view fraction and error per frame, regions B and C "
                                "(cf. thesis Figure 24)", "frame (0.5 s apart)",
                          panels(lambda f: f, lambda f: vis[f][1] in ("B", "C")), edges=edges,
                          shades=[(out[0] - 0.5, out[-1] + 0.5, "tail out of view")], lines=True)
        rep.image(path, "Thesis geometry, regions B and C frame by frame: fraction of the receiver's vertices in "
                        "view (sidecar in_view) and error = estimate - truth per degree of freedom, shelled model; "
                        "the default geometry's same frames in grey. Shaded: the tail out of view")
    near = set(before + out + after)
    lo = min(vis[f][0] for f in near)
    hi = max(vis[f][0] for f in near)
    path = ctx.out / "conops_thesis_tail.png"
    plots.panels_vs_x(path, "Thesis geometry around the tail-out stretch", "range from the left camera (m)",
                      panels(lambda f: vis[f][0], lambda f: lo - 0.3 <= vis[f][0] <= hi + 0.3),
                      edges=[(38.0, "B | C (38 m)")], xlim=(lo - 0.3, hi + 0.3),
                      shades=[(vis[out[-1]][0], vis[out[0]][0], "tail out of view")], lines=True)
    rep.image(path, f"The same around the tail-out stretch, by range ({lo:.1f}-{hi:.1f} m: the frames with the "
                    "tail out and their neighbours in the table above)")


@register("conops", order=2,
          help="thesis Experiment 2: shelled vs full on the CONOPS path (Tables 4-5, Figures 20-24); "
               "--background renders it over terrain, clouds or a sky with a horizon; --geometry thesis on the "
               "thesis rig, where the tail leaves the view")
def run(ctx):
    flat = ctx.background == "flat"
    thesis = ctx.geometry == "thesis"
    geo = GEOMETRIES[ctx.geometry]
    name = dataset_name(ctx.geometry, ctx.background)
    render_extra = () if flat else ("--background", ctx.background, "--depth")
    res = render_and_analyze(ctx, name, geo.flight_path, ctx.sel[geo.selection], render_extra=render_extra,
                             rig=geo.rig, more_overlays=_least_in_view_overlay if thesis else None)

    rep = Report(ctx, "Experiment 2: CONOPS flight path, shelled versus full reference model"
                 + (", thesis geometry (tail out of view)" if thesis else "")
                 + ("" if flat else f", {ctx.background} background"))
    if not flat:
        rep.p(f"Rendered with `--background {ctx.background}` (docs/rendering.md, \"Backgrounds\": tanker at "
              "7,000 m, level) and `--depth`; the calibration boards keep the flat sky. The estimator is "
              "unchanged; nothing here uses the truth except to measure.")
    if thesis:
        rep.p("Thesis section 4.2 (Tables 4-5, Figures 20-24) on the thesis geometry (issue 9, item 1): "
              f"`{geo.rig}` (the 900 px cameras of `scenes/rig.json` pitched 41 deg down instead of 30, the same "
              f"contact position, 11 deg above the optical axis) and `{geo.flight_path}` (the approach of "
              "`conops.csv`, 609 samples with the same ranges and attitudes, flown 32 deg below the horizontal "
              "through the left camera down to 45 m and level at the contact height from 37 m; "
              "flightpaths/README.md). The calibration boards are rendered with the same rig. MSAA x16; analyzed: "
              f"{selection_text(res.selection)}. At most 30 ICP iterations, centroid seed, calibration from the "
              "dataset's own x16 boards. Regions: A 70-175 m, B 38-70 m, C 32-38 m. The thesis numbers in the "
              "tables are its own (its geometry lost the tail at 38-42 m). Difference (%) = 100 (full - "
              "shelled) / full. Frames the analyzer could not measure are left out of its statistics (\"Frames "
              "ok/all\").")
    else:
        rep.p("Thesis section 4.2 (Tables 4-5, Figures 20-24). `flightpaths/conops.csv` (609 samples, 175 m to the "
              f"contact position at 32 m, attitude up to 2.8 deg) rendered with MSAA x16; analyzed: "
              f"{selection_text(res.selection)}. At most 30 ICP iterations, centroid seed, calibration from the "
              "dataset's own x16 boards. Regions: A 70-175 m, B 38-70 m, C 32-38 m. The thesis reports only "
              "position for region A (\"orientation values in region A ... were inconsistent\"). Difference (%) = "
              "100 (full - shelled) / full. Frames the analyzer could not measure are left out of its statistics "
              "(\"Frames ok/all\").")
    rep.p(f"As in Experiment 1, the analyzer's default ICP pairing (`{res.pairing}`) and the model-to-sensed "
          f"pairing (`{res.pairing_tp}`), under which unseen model surfaces pull the estimate, are both reported.")
    both_pairings(rep, res, _tables)
    _registration_details(rep, res)
    preset_dirs = _presets(ctx, rep, res)
    if not flat:
        _cloud_truth(rep, [("published pipeline", res.frames["shelled"])]
                     + [(label, read_frames(d)) for (label, _), d in zip(PRESETS, preset_dirs)])
    control_dirs = []
    if thesis:
        control = _control(ctx, res.selection, render_extra)
        control_dirs = list(control[0].values())
        _geometries(rep, res, preset_dirs, control)
        vis, band = _tail(ctx, rep, res, preset_dirs, control)
        _figures(ctx, rep, res, vis, shade=band)
    else:
        vis = _partial_visibility(rep, res)
        _figures(ctx, rep, res, vis)
    return conclude(ctx, rep, res.run_dirs() + preset_dirs + control_dirs)
