"""The skeleton that Experiments 1 (characterization) and 2 (CONOPS) share.

One flight path rendered with MSAA x16 (and its calibration boards), analyzed
with both reference models and both ICP pairing directions; the thesis's
mean absolute and RMS tables for each pairing, error figures per model, the
provenance sections.

The thesis's shelled-model argument (section 4.1: the full model's surfaces
that the cameras never see hurt the registration) holds for ICP that pairs
every MODEL point with its nearest sensed point. Experiments 1 and 2 are
therefore run with the analyzer's default pairing and again with that one.
"""

from dataclasses import dataclass
from pathlib import Path

from . import plots, report
from .outputs import group_table, group_table_counts, pairing_of, read_frames, read_json, read_summary, sidecar
from .report import COMPARISON_HEADERS, comparison_rows
from .runner import analyze, render_calib, render_frames, selected_frames
from .thesis import THESIS

THESIS_PAIRING = ("--correspondence", "model_to_sensed")
MODELS = ("shelled", "full")  # analysis order


@dataclass
class Runs:
    """Both models' analyses of one dataset, with each pairing."""
    dataset: Path
    selection: object
    runs: dict          # model -> run folder, the analyzer's default pairing
    runs_tp: dict       # model -> run folder, THESIS_PAIRING
    summaries: dict     # model -> summary.json, default pairing
    summaries_tp: dict  # model -> summary.json, THESIS_PAIRING
    frames: dict        # model -> frames.csv rows, default pairing
    pairing: str        # the default pairing's name (run.json)
    pairing_tp: str     # THESIS_PAIRING's name (run.json)
    overlay_frames: dict  # region -> frame dumped by the shelled run (default pairing)

    def run_dirs(self):
        return [self.runs["shelled"], self.runs["full"], self.runs_tp["shelled"], self.runs_tp["full"]]


def frames_per_region(dataset, selection):
    """One analyzed frame per region (the middle one of the region's selected frames): {region: frame}."""
    count = read_json(dataset / "manifest.json")["frames"]["count"]
    by_region = {}
    for i in selected_frames(selection, count):
        by_region.setdefault(sidecar(dataset, i)["region"], []).append(i)
    return {g: f[len(f) // 2] for g, f in sorted(by_region.items()) if g != "none"}


def dump_option(overlay_frames):
    """aar-analyze's --dump-frames for {label: frame} (none when empty)."""
    frames = sorted(set(overlay_frames.values()))
    return ("--dump-frames", ",".join(str(f) for f in frames)) if frames else ()


def render_and_analyze(ctx, dataset_name, flight_path, selection, render_extra=(), rig=None, more_overlays=None):
    """Renders `flight_path` (with `render_extra` flags) and its boards at x16 into `dataset_name`, both with
    `rig` when given (else aar-render's default scenes/rig.json); four analyses (models x pairings). The
    shelled run with the default pairing also dumps one frame per region (`--dump-frames`), and the frames
    more_overlays(dataset, selection) returns ({label: frame}, labels other than the region letters)."""
    ds = ctx.dataset(dataset_name)
    rig_args = ("--rig", rig) if rig else ()
    render_calib(ctx, ds, 16, rig)
    render_frames(ctx, ds, 16, flight_path, selection, tuple(render_extra) + rig_args)
    overlay_frames = frames_per_region(ds, selection)
    if more_overlays:
        overlay_frames.update(more_overlays(ds, selection))
    dump = dump_option(overlay_frames)
    runs = {m: analyze(ctx, f"{dataset_name}-{m}", ds, m, selection, extra=dump if m == "shelled" else ())
            for m in MODELS}
    runs_tp = {m: analyze(ctx, f"{dataset_name}-{m}-model-to-sensed", ds, m, selection, extra=THESIS_PAIRING)
               for m in MODELS}
    return Runs(dataset=ds, selection=selection, runs=runs, runs_tp=runs_tp, overlay_frames=overlay_frames,
                summaries={m: read_summary(runs[m]) for m in runs},
                summaries_tp={m: read_summary(runs_tp[m]) for m in runs_tp},
                frames={m: read_frames(runs[m]) for m in runs},
                pairing=pairing_of(runs["shelled"]), pairing_tp=pairing_of(runs_tp["shelled"]))


def model_tables(rep, summaries, note, groups, group_label, tables):
    """The thesis's full-versus-shelled tables from {model: summary.json}.

    tables: (title, summary.json statistic, THESIS table) each; with the
    thesis's Difference (%) rows, 100 (full - shelled) / full, where it
    prints them.
    """
    km = {"Full Model": (summaries["full"], "full"), "Shelled Model": (summaries["shelled"], "shelled")}
    models = ("Full Model", "Shelled Model")
    counts = group_table_counts(km, groups)
    for title, kind, tab in tables:
        thesis = {g: {"Full Model": THESIS[tab][g]["full"], "Shelled Model": THESIS[tab][g]["shelled"]}
                  for g in groups}
        diff = None
        if all("diff" in THESIS[tab][g] for g in groups):
            diff = ("Full Model", "Shelled Model", {g: THESIS[tab][g]["diff"] for g in groups})
        rep.h(f"{title}{note}", 3)
        rep.table(COMPARISON_HEADERS, comparison_rows(
            groups, models, group_table(km, groups, kind), thesis, diff=diff, counts=counts,
            group_label=group_label))


def both_pairings(rep, res, tables):
    """tables(rep, summaries, note) once per pairing, each under its heading."""
    rep.h(f"With the analyzer's default ICP pairing (`{res.pairing}`)")
    tables(rep, res.summaries, f" ({res.pairing})")
    rep.h(f"With the model-to-sensed ICP pairing (`{res.pairing_tp}`)")
    tables(rep, res.summaries_tp, f" ({res.pairing_tp})")


def model_error_plots(ctx, rep, res, stem, figures, what, guides):
    """Position and orientation error figures per model, <stem>_<model>_<position|orientation>.png;
    figures: ((model, (thesis figure for position, for orientation)), ...) in report order."""
    for m, figs in figures:
        for path, cap in report.error_plots(ctx, res.frames[m], f"{stem}_{m}",
                                            f"{m} reference model, {res.pairing} pairing, {what}", figs, guides):
            rep.image(path, cap)


def region_overlays(ctx, rep, res, stem):
    """One overlay of the registered shelled model on the left image per region (`--dump-frames`),
    cropped around the model, beside the report as <stem>_overlay_<region>.png."""
    rep.h("The registered model on the left image, one frame per region")
    rep.p("`aar-analyze run --dump-frames` of the shelled run (default pairing): the reference model's points at "
          "the estimated pose in green, the estimated receiver origin as a green cross and the true one as a red "
          "cross; cropped around the model. The run's `frames/` folder also holds each frame's colour-mapped "
          "disparity, and the sensed cloud and the registered model as PLY.")
    rows = {r["frame"]: r for r in res.frames["shelled"]}
    for g, frame in sorted(res.overlay_frames.items()):
        source = res.runs["shelled"] / "frames" / f"{frame:06d}_overlay.png"
        row = rows.get(frame, {})
        what = f"Region {g}" if len(g) == 1 else g[0].upper() + g[1:]
        if not source.is_file():
            rep.p(f"{what}, frame {frame}: no estimate, no overlay ({row.get('status', 'not analyzed')}).")
            continue
        name = g if len(g) == 1 else "".join(c if c.isalnum() else "_" for c in g)
        path = plots.crop_to_green(source, ctx.out / f"{stem}_overlay_{name}.png")
        status = "ok" if row["status"] == "ok" else "not measured: " + row["status"].split(": ", 1)[-1]
        rep.image(path, f"{what}: frame {frame} at {row['range_m']:.1f} m, shelled model registered "
                        f"(status {status})")
