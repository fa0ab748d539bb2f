"""Experiment 2 on the thesis geometry (issue 9, item 1): where the receiver's tail leaves the view.

scenes/rig-thesis.json with flightpaths/conops-level.csv puts the T-tail out of the top of the images at
about 39 m and back in view inside region C (thesis Figure 24). From the sidecars' `in_view` and the runs of
conops.py: where the tail leaves and returns, which image edge, the errors with the tail out against the
neighbouring frames in view and against the same frames on the default geometry (the control), per frame and
per region, and the figures. The pipelines are given as {label: run folder}, labels TAIL_PIPELINES.
"""

from . import plots
from .outputs import ok_rows, read_frames, read_json, read_summary, sidecar
from .report import fmt, mean_abs
from .runner import selected_frames, selection_text
from .thesis import COMPONENT_HEADERS, COMPONENTS, REGIONS

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


def least_in_view_overlay(dataset, selection):
    """more_overlays for render_and_analyze: the selected frame with the least of the receiver in view."""
    count = read_json(dataset / "manifest.json")["frames"]["count"]
    vis = _in_view(dataset, selected_frames(selection, count))
    frame = min(vis, key=lambda f: (min(vis[f][2], vis[f][3]), f))
    return {"tail out of view": frame} if min(vis[frame][2], vis[frame][3]) < 1.0 else {}


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


def tail(ctx, rep, res, runs, control):
    """Where the tail leaves and returns, the in-view fraction per frame, the errors with the tail out against
    the neighbouring frames and against the same frames on the default geometry; figures. Returns the
    visibility list _figures takes and the band to shade."""
    control_runs, control_ds, control_path = control
    frames = [r["frame"] for r in res.frames["shelled"]]
    vis = _in_view(res.dataset, frames)
    control_vis = _in_view(control_ds, frames)
    rows = {label: {r["frame"]: r for r in read_frames(d)} for label, d in runs.items()}
    crows = {label: {r["frame"]: r for r in read_frames(d)} for label, d in control_runs.items()}
    drange = max(abs(vis[f][0] - control_vis[f][0]) for f in frames)

    rep.h("Where the tail leaves the view (thesis geometry; cf. thesis Figure 24)")
    rep.p("`in_view` in each frame's sidecar is the fraction of the receiver model's 27,714 vertices that project "
          "inside the image (docs/dataset-format.md), for the left and the right camera. On this rig the receiver's "
          "top edge, the T-tail, is near the top of the images, and the level final approach at the contact height "
          "takes it out of the frame (flightpaths/README.md, `conops-level.csv`). Control: the same frame indices "
          f"of `{control_path}` on `scenes/rig.json` (`{control_ds.name}`), the same approach "
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


def geometries(rep, runs, control):
    """Per region, the thesis geometry against the default geometry on the same frames."""
    control_runs = control[0]
    rep.h("The two geometries per region (shelled model)")
    rep.p("Mean absolute error per region on the thesis geometry and on the same frames of the default geometry "
          "(the control above). Regions B and C include the frames with the tail out.")
    rows = []
    for g in REGIONS:
        for label in TAIL_PIPELINES:
            for rig, d in (("thesis", runs[label]), ("default", control_runs[label])):
                st = read_summary(d)["models"]["shelled"][g]
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
