"""A self-contained HTML report of an `aar-analyze run` folder (docs/report.md).

    python3 -m aar_stereo.report RUN [--out FILE] [--dataset DIR]

One HTML file with everything inline (plots as SVG, images as PNG, CSS; no
script, nothing fetched): the run's record, the region tables, error against
range per degree of freedom, the ICP's iterations and time, the worst frames
with their sensed cloud and the registered model's outline over the left
image, the calibration's residuals and the temporal filter. The same run
folder (and dataset) gives the same bytes.
"""

import argparse
import os
import sys
from functools import cached_property
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .dataset import open_dataset  # noqa: E402
from .errors import DataError  # noqa: E402
from .formats import read_json, sha256_file  # noqa: E402
from .report_parts import (crop, esc, figure, flatten, fmt, mark_regions, project, silhouette, table,  # noqa: E402
                           transform)
from .run import open_run  # noqa: E402

# Fixed salt for the SVG's ids, matplotlib's own font: the same input gives the same bytes.
matplotlib.rcParams.update({"svg.hashsalt": "aar-report", "font.family": "DejaVu Sans", "font.size": 8,
                            "axes.grid": True, "grid.alpha": 0.3})

DOF = (("x_m", "X (m)"), ("y_m", "Y (m)"), ("z_m", "Z (m)"),
       ("roll_deg", "Roll (deg)"), ("pitch_deg", "Pitch (deg)"), ("yaw_deg", "Yaw (deg)"))
GROUP_ORDER = ("A", "B", "C", "all", "20-60", "60-110")
STAGES = ("ms_load", "ms_rectify", "ms_disparity", "ms_reproject", "ms_icp")
WORST = 6
CSS = """
body { font-family: "DejaVu Sans", sans-serif; font-size: 14px; margin: 1.5em auto; max-width: 1200px; color: #222; }
h1 { font-size: 1.6em; } h2 { border-bottom: 2px solid #4a6fa5; padding-bottom: 0.2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: 0.6em 0; } caption { text-align: left; font-weight: bold; padding: 0.3em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; } th { background: #eef2f8; }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
.note { background: #fff6d6; border-left: 4px solid #e0b000; padding: 0.4em 0.8em; margin: 0.5em 0; }
figure { margin: 0.8em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
.frames { display: grid; grid-template-columns: repeat(auto-fill, minmax(360px, 1fr)); gap: 1em; }
code, pre { background: #f4f4f4; } pre { padding: 0.5em; white-space: pre-wrap; word-break: break-all; }
"""


class Report:
    """The report's parts, built from a run (and its dataset when found); `notes` lists what is missing."""

    def __init__(self, run, dataset, dataset_searched):
        self.run = run
        self.dataset = dataset
        self.notes = []
        if dataset is None:
            self.notes.append("The run's dataset was not found (looked for a manifest.json with run.json's "
                              f"SHA-256 in {dataset_searched}; name it with --dataset DIR): the worst frames "
                              "are drawn over the dumps' overlays, without the plain left image.")
        self.model = run.record.get("model")
        self.columns = set(run.frames[0]) if len(run) else set()
        self.camera_from_tanker = np.array(run.record["bop"]["camera_from_tanker"], dtype=float).reshape(4, 4)
        self.calibration = run.calibration if (run.path / "calibration.yaml").is_file() else None

    def column(self, name):
        """A float column, NaN throughout when frames.csv lacks it."""
        return self.run.column(name) if name in self.columns else np.full(len(self.run), np.nan)

    def record(self):
        r = self.run.record
        statuses = self.run.column("status") if len(self.run) else np.array([], dtype=str)
        ok = int((statuses == "ok").sum())
        timing = self.run.summary.get("timing", {}).get(self.model, {}).get("all") or {}
        total_s = np.nansum(self.column("ms_total")) / 1000
        dataset = str(self.dataset.path.resolve()) if self.dataset else "not found"
        rows = [("run folder", self.run.path.resolve().name),
                ("dataset", dataset),
                ("dataset manifest SHA-256", r.get("dataset_manifest_sha256")),
                ("model", f"{self.model} ({r.get('reference_points')} reference points)"),
                ("preset", r.get("options", {}).get("preset")),
                ("calibration", ", ".join(f"{k}: {v}" for k, v in r.get("calibration", {}).items())),
                ("frames selected", r.get("frames")),
                ("frames analyzed", f"{r.get('frames_analyzed')} ({ok} ok, {len(statuses) - ok} not measured)"),
                ("time per frame (mean)", f"{fmt(timing.get('total_ms_mean'))} ms, of which ICP "
                                          f"{fmt(timing.get('icp_ms_mean'))} ms (std {fmt(timing.get('icp_ms_std'))})"),
                ("time, all frames", f"{fmt(total_s)} s (sum of frames.csv's ms_total)"),
                ("receiver diameter (BOP)", f"{fmt(r.get('bop', {}).get('diameter_m'))} m")]
        options = table(("option", "value"), flatten(r.get("options", {})))
        failed = [(f["frame"], f["status"]) for f in self.run if f["status"] != "ok"]
        failures = table(("frame", "status"), failed, "Frames not measured") if failed else ""
        return (table(None, rows) + failures +
                f"<details><summary>Options (run.json)</summary>{options}</details>\n")

    def regions(self):
        out = []
        for model, groups in self.run.summary.get("models", {}).items():
            names = [g for g in GROUP_ORDER if g in groups] + [g for g in groups if g not in GROUP_ORDER]
            used = [g for g in names if groups[g].get("frames")]
            if len(used) < len(names):
                out.append(f"<p>Groups without frames, left out: {esc(', '.join(g for g in names if g not in used))}."
                           "</p>\n")
            head = ("group", "ok / frames") + tuple(label for _, label in DOF)
            for key, caption in (("mean_abs_error", "Mean absolute error"), ("rms_error", "RMS error")):
                rows = [(g, f"{groups[g]['ok']} / {groups[g]['frames']}") +
                        tuple((groups[g].get(key) or {}).get(c) for c, _ in DOF) for g in used]
                out.append(table(head, rows, f"{caption}, model {model}"))
            vsd = any("ar_vsd" in groups[g].get("bop", {}) for g in used)
            scores = (("ar_vsd", "AR VSD"),) * vsd + (("ar_mssd", "AR MSSD"), ("ar_mspd", "AR MSPD")) + \
                (("ar", "AR"),) * vsd + (("ar_mssd_mspd", "AR (MSSD, MSPD)"), ("add_recall", "ADD"),
                                         ("adds_recall", "ADD-S"))
            rows = [(g,) + tuple(groups[g].get("bop", {}).get(k) for k, _ in scores) +
                    (groups[g].get("icp_iterations_mean"), groups[g].get("icp_converged"),
                     groups[g].get("icp_rmse_m_mean"), groups[g].get("sensed_points_mean")) for g in used]
            out.append(table(("group",) + tuple(label for _, label in scores) +
                             ("ICP iterations", "ICP converged", "ICP RMSE (m)", "sensed points"), rows,
                             f"BOP scores (docs/analysis.md, \"BOP scores\") and ICP, model {model}"))
        return "".join(out)

    def error_vs_range(self):
        ranges, ok = self.column("range_m"), self.run.column("status") == "ok"
        fig, axes = plt.subplots(2, 3, figsize=(11.5, 6), constrained_layout=True)
        for ax, (name, label) in zip(axes.flat, DOF):
            error = self.column("err_" + name)
            rejected = ~ok & np.isfinite(error)
            ax.plot(ranges[ok], error[ok], ".", markersize=4, color="C0", label="ok")
            if rejected.any():
                ax.plot(ranges[rejected], error[rejected], "x", markersize=5, color="C3", label="rejected")
            ax.axhline(0.0, color="black", linewidth=0.6)
            mark_regions(ax, ranges)
            ax.set_xlabel("range (m)")
            ax.set_ylabel("error " + label)
        axes.flat[0].legend(loc="best")
        return ("<p>Estimate minus truth of every frame with an estimate (rejected frames as red crosses), "
                "dashed lines at the region boundaries.</p>\n" + figure(fig, "error against range"))

    def icp(self):
        frames = self.run.column("frame")
        iterations = self.run.column("icp_iterations")
        converged = self.run.column("icp_converged")
        fig, (top, bottom) = plt.subplots(2, 1, figsize=(11.5, 5.5), sharex=True, constrained_layout=True)
        top.plot(frames, iterations, ".-", linewidth=0.6, markersize=4, label="converged")
        top.plot(frames[~converged], iterations[~converged], "x", color="C3", markersize=6, label="not converged")
        top.set_ylabel("ICP iterations")
        top.legend(loc="best")
        stages = [np.nan_to_num(self.column(s)) for s in STAGES]
        bottom.stackplot(frames, stages, labels=[s[3:] for s in STAGES], alpha=0.8)
        bottom.plot(frames, self.column("ms_total"), color="black", linewidth=0.8, label="total")
        bottom.set_xlabel("frame")
        bottom.set_ylabel("time per frame (ms)")
        bottom.legend(loc="upper left", ncol=6)
        return ("<p>frames.csv's <code>icp_iterations</code>, <code>icp_converged</code> and the stage times "
                "<code>ms_*</code> (stacked; a timing, unlike the rest of the run).</p>\n" +
                figure(fig, "ICP iterations and time per frame"))

    def worst(self):
        errors = np.column_stack([self.column("err_" + name) for name, _ in DOF])
        estimated = np.flatnonzero(np.isfinite(errors).all(axis=1))
        if estimated.size == 0:
            return "<p>No frame has an estimate.</p>\n"
        rms = np.sqrt(np.mean(errors[estimated] ** 2, axis=0))
        score = np.mean(np.abs(errors) / np.where(rms > 0, rms, 1.0), axis=1)
        order = sorted(estimated, key=lambda k: (-score[k], k))[:WORST]
        rows = [(self.run[k]["frame"], self.run[k]["region"], self.run[k]["range_m"], self.run[k]["status"],
                 score[k]) + tuple(errors[k]) for k in order]
        out = ["<p>The frames with the largest combined error: each degree of freedom's absolute error divided "
               "by its RMS over the run's estimated frames, averaged over the six.</p>\n",
               table(("frame", "region", "range (m)", "status", "combined") + tuple(l for _, l in DOF), rows)]
        missing = [self.run[k]["frame"] for k in order if self.run[k]["frame"] not in self.run.dumps]
        if missing:
            out.append(f'<p class="note">No frame dump for {esc(", ".join(map(str, missing)))}: their sensed '
                       "clouds are not in the run folder. This command writes them (with the run's other "
                       f"options, if it had any):</p>\n<pre>{esc(self.dump_command(missing))}</pre>\n")
        worst = [self.run[k]["frame"] for k in order]
        out.append('<div class="frames">' + "".join(map(self.frame_picture, worst)) + "</div>\n")
        others = [frame for frame in self.run.dumps if frame not in worst]
        if others:
            out.append("<h3>The other frames dumped</h3>\n"
                       '<div class="frames">' + "".join(map(self.frame_picture, others)) + "</div>\n")
        return "".join(out)

    def dump_command(self, frames):
        r = self.run.record
        dataset = str(self.dataset.path.resolve()) if self.dataset else "DATASET"
        calibration = r.get("calibration", {})
        if "calibrated_from" in calibration:
            source = []
        elif self.uses_ideal_calibration():
            source = ["--calibration", str(self.dataset.path.resolve() / "calibration_ideal.yaml")]
        else:
            source = ["--calibration", calibration.get("file", "FILE")]
        preset = r.get("options", {}).get("preset", "default")
        return " ".join(["aar-analyze", "run", dataset, "--frames", str(r.get("frames")), "--model", self.model] +
                        source + ([] if preset == "default" else ["--preset", preset]) +
                        ["--dump-frames", ",".join(map(str, frames)), "--out", str(self.run.path.resolve())])

    @cached_property
    def estimates(self):
        """{frame: estimated camera_from_receiver (4 x 4, metres)} of bop_results.csv (the ok frames)."""
        if not (self.run.path / "bop_results.csv").is_file():
            return {}
        out = {}
        for r in self.run.bop_results:
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = r["R"], r["t"] / 1000.0
            out[r["im_id"]] = pose
        return out

    def frame_picture(self, frame):
        """The left image (or the dump's overlay) with the dumped sensed cloud and the registered model's outline
        (from the dump, else the reference cloud at bop_results.csv's estimate)."""
        dump = self.run.dumps.get(frame)
        files = dump.files if dump else {}
        if self.calibration is None:
            return f"<div><p><b>Frame {frame}</b>: no calibration.yaml in the run folder to project with.</p></div>\n"
        if self.dataset is not None:
            image, backdrop = self.dataset.frame(frame).left(), "the left image"
        elif "overlay" in files:
            image, backdrop = dump.overlay(), "the dump's overlay (the model's points in green)"
        else:
            return f"<div><p><b>Frame {frame}</b>: no left image (dataset not found, no overlay dumped).</p></div>\n"
        if "model" in files:
            model = project(transform(self.camera_from_tanker, dump.model()), self.calibration)
        elif frame in self.estimates:
            model = project(transform(self.estimates[frame], self.run.reference_cloud()), self.calibration)
        else:
            model = None
        sensed = project(transform(self.camera_from_tanker, dump.sensed()), self.calibration) \
            if "sensed" in files else None
        height, width = image.shape[:2]
        left, right, top, bottom = crop([p for p in (model, sensed) if p is not None], (width, height))
        fig, ax = plt.subplots(figsize=(4.8, 0.3 + 4.8 * (bottom - top) / (right - left)), constrained_layout=True)
        # A thermal rig's view is one channel of brightness temperature: grey, coldest to hottest.
        ax.imshow(image, interpolation="nearest", cmap="gray" if image.ndim == 2 else None)
        ax.set_xlim(left, right)
        ax.set_ylim(bottom, top)
        parts = []
        if model is not None:
            ax.contour(silhouette(model, (width, height), 3), levels=[0.5], colors="yellow", linewidths=1.0)
            parts.append("yellow: the registered model's outline")
        if sensed is not None:
            ax.scatter(sensed[:, 0], sensed[:, 1], s=0.6, color="magenta", linewidths=0)
            parts.append(f"magenta: the sensed cloud ({len(sensed)} points)")
        else:
            parts.append("no sensed cloud (" + ("not in the frame dump" if dump else "no frame dump") + ")")
        ax.set_axis_off()
        ax.set_title(f"frame {frame}")
        caption = f"Frame {frame} over {backdrop}; " + "; ".join(parts) + "."
        return f"<div>{figure(fig, f'frame {frame}', 'png')}<p>{esc(caption)}</p></div>\n"

    def calibration_part(self):
        source = self.run.record.get("calibration", {})
        report, where = None, None
        if "calibrated_from" in source:
            report, where = self.run.calibration_report, "this run calibrated from the dataset's boards"
        else:
            found = self.find_calibration_report(source.get("sha256"))
            if found:
                report, where = read_json(found), f"{found.parent.name}/calibration_report.json"
        if report is None:
            return f'<p class="note">{esc(self.calibration_source(source))}</p>\n'
        scalars = [(k, v) for k, v in flatten(report) if not k.startswith(("pairs.", "Q", "versus_ideal.q_percent"))]
        pairs = report.get("pairs", [])
        unused = [(k, p.get("reason")) for k, p in enumerate(pairs) if not p.get("used")]
        residuals = [(k, report[k]) for k in ("left_rms_px", "right_rms_px", "rms_reprojection_px",
                                              "epipolar_error_px") if isinstance(report.get(k), (int, float))]
        fig, ax = plt.subplots(figsize=(6, 2.4), constrained_layout=True)
        ax.barh([k for k, _ in residuals][::-1], [v for _, v in residuals][::-1], color="C0")
        ax.set_xlabel("px")
        return (f"<p>From {esc(where)}: {len(pairs) - len(unused)} of {len(pairs)} board pairs used. The report "
                "holds the residuals over all boards (no per-board errors).</p>\n" +
                figure(fig, "calibration residuals") + table(None, scalars) +
                (table(("pair", "reason"), unused, "Board pairs not used") if unused else ""))

    def find_calibration_report(self, sha256):
        """calibration_report.json beside a calibration.yaml with the run's calibration's SHA-256, among the
        run folder's siblings (where `aar-analyze calibrate` writes by default)."""
        parent = self.run.path.resolve().parent
        for yaml in sorted(parent.glob("*/calibration.yaml")):
            report = yaml.with_name("calibration_report.json")
            if report.is_file() and sha256_file(yaml) == sha256:
                return report
        return None

    def uses_ideal_calibration(self):
        """Whether the run's calibration is its dataset's calibration_ideal.yaml (by SHA-256)."""
        return self.dataset is not None and self.run.record.get("calibration", {}).get("sha256") == \
            sha256_file(self.dataset.path / "calibration_ideal.yaml")

    def calibration_source(self, source):
        name = source.get("file")
        if self.uses_ideal_calibration() or (self.dataset is None and name == "calibration_ideal.yaml"):
            return (f"The run used the ideal calibration ({name}, from the rig's geometry): there are no "
                    "calibration residuals.")
        return (f"The run used the calibration {name} (SHA-256 {source.get('sha256')}); no calibration_report.json "
                "was found beside a calibration.yaml with that SHA-256 in the run folder's sibling folders.")

    def filtered(self):
        error = {name: self.column("err_" + name) for name, _ in DOF}
        filtered = {name: self.column("filt_err_" + name) for name, _ in DOF}
        if not any(np.isfinite(v).any() for v in filtered.values()):
            return "<p>This run has no filtered poses (frames.csv's <code>filt_*</code> columns are empty).</p>\n"
        frames = self.run.column("frame")
        fig, axes = plt.subplots(2, 3, figsize=(11.5, 5.5), sharex=True, constrained_layout=True)
        for ax, (name, label) in zip(axes.flat, DOF):
            ax.plot(frames, error[name], ".", markersize=3, color="0.5", label="per frame")
            ax.plot(frames, filtered[name], "-", linewidth=1.0, color="C1", label="filtered")
            ax.set_ylabel("error " + label)
        for ax in axes[1]:
            ax.set_xlabel("frame")
        axes.flat[0].legend(loc="best")
        rows = []
        groups = self.run.summary.get("models", {}).get(self.model, {})
        for g in [g for g in GROUP_ORDER if (groups.get(g) or {}).get("frames")]:
            for key, label in (("mean_abs_error", "error, per frame"), ("filtered_mean_abs_error", "error, filtered"),
                               ("jitter_rms", "jitter, per frame"), ("filtered_jitter_rms", "jitter, filtered")):
                rows.append((g, label) + tuple((groups[g].get(key) or {}).get(c) for c, _ in DOF))
        return ("<p>frames.csv's <code>filt_err_*</code> (the causal constant-velocity filter) against the "
                "per-frame error; jitter: the RMS change of the error from one frame to the next.</p>\n" +
                figure(fig, "filtered error") +
                table(("group", "") + tuple(l for _, l in DOF), rows, "Mean absolute error and jitter"))

    def html(self):
        sections = [("record", "The run", self.record), ("regions", "Region tables", self.regions),
                    ("error-vs-range", "Error against range", self.error_vs_range),
                    ("icp", "ICP iterations and time", self.icp), ("worst", "Worst frames", self.worst),
                    ("calibration", "Calibration", self.calibration_part),
                    ("filter", "Temporal filter", self.filtered)]
        bodies = [(key, title, build() if len(self.run) or key in ("record", "calibration") else
                   "<p>The run has no frames.</p>\n") for key, title, build in sections]
        name = esc(self.run.path.resolve().name)
        nav = " · ".join(f'<a href="#{key}">{esc(title)}</a>' for key, title, _ in bodies)
        notes = "".join(f'<p class="note">{esc(n)}</p>\n' for n in self.notes)
        parts = "".join(f'<section id="{key}">\n<h2>{esc(title)}</h2>\n{body}</section>\n'
                        for key, title, body in bodies)
        return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                f"<title>aar-analyze run {name}</title>\n<link rel=\"icon\" href=\"data:,\">\n<style>{CSS}</style>\n"
                f"</head>\n<body>\n<h1>aar-analyze run {name}</h1>\n<nav>{nav}</nav>\n{notes}{parts}</body>\n</html>\n")


def find_dataset(run):
    """The dataset whose manifest.json has run.json's SHA-256, among the folders in `datasets/` of the current
    folder and of the run folder's parent's parent (results/x -> datasets/); (dataset or None, where looked)."""
    places = sorted({Path("datasets").resolve(), run.path.resolve().parent.parent / "datasets"})
    wanted = run.record.get("dataset_manifest_sha256")
    for place in places:
        for manifest in sorted(place.glob("*/manifest.json")):
            if sha256_file(manifest) == wanted:
                return open_dataset(manifest.parent, verify=False), places
    return None, places


def write_report(run_path, out=None, dataset_path=None):
    """Writes the report of the run folder `run_path` to `out` (default RUN/report.html) through a temporary
    file in the same folder; returns the path. Raises DataError for a missing or malformed run file."""
    run = open_run(run_path)
    if dataset_path is not None:
        dataset, searched = open_dataset(dataset_path, verify=False), [Path(dataset_path)]
    else:
        dataset, searched = find_dataset(run)
    text = Report(run, dataset, ", ".join(map(str, searched))).html()
    out = Path(out) if out is not None else run.path / "report.html"
    temporary = out.with_name(f".{out.name}.{os.getpid()}.tmp")
    file = open(temporary, "xb")
    try:
        with file:
            file.write(text.encode("utf-8"))
        os.replace(temporary, out)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m aar_stereo.report", description=__doc__.split("\n\n")[0])
    parser.add_argument("run", help="an aar-analyze run (or merge) output folder")
    parser.add_argument("--out", help="the HTML file to write (default RUN/report.html)")
    parser.add_argument("--dataset", help="the run's dataset (default: found by its manifest's SHA-256 in datasets/)")
    args = parser.parse_args(argv)
    try:
        print(write_report(args.run, args.out, args.dataset))
    except (DataError, OSError) as error:
        print(error, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
