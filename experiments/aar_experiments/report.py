"""Writing report.md: text, tables, our numbers beside the thesis's, figures, provenance.

Every experiment builds a Report and ends with conclude(), which adds the
commands run, the datasets, the software and the machine, writes report.md
and checks that it and every figure exist.
"""

import math
import os
import platform
from pathlib import Path

import matplotlib

from . import plots
from .outputs import ok_rows, read_run_json
from .runner import (LOG, ExperimentError, analyzer_version, binary_hashes, cpu_model, dataset_info,
                     dpkg_version, rel)
from .thesis import COMPONENT_HEADERS, COMPONENTS


def fmt(value, digits=3):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return f"{value:.{digits}f}"


def ratio(ours, thesis):
    if ours is None or thesis is None or thesis == 0:
        return None
    return ours / thesis


def pct_diff(ref, new):
    """Thesis "Difference (%)": reduction of `new` relative to `ref`, 100 (ref - new) / ref."""
    if ref is None or new is None or ref == 0:
        return None
    return 100.0 * (ref - new) / ref


def mean_abs(values):
    values = [abs(v) for v in values if v is not None]
    return sum(values) / len(values) if values else None


def md_table(headers, rows, align=None):
    align = align or (["---"] + ["---:"] * (len(headers) - 1))
    out = ["| " + " | ".join(headers) + " |", "| " + " | ".join(align) + " |"]
    for row in rows:
        out.append("| " + " | ".join(str(c) for c in row) + " |")
    return "\n".join(out)


class Report:
    def __init__(self, ctx, title):
        self.ctx = ctx
        self.lines = [f"# {title}", ""]
        if ctx.quick:
            self.p("**QUICK MODE** (`--quick`): a few frames per region or range bin. These numbers are a "
                   "smoke test of the pipeline and the report, not a reproduction of the thesis.")

    def h(self, text, level=2):
        self.lines += ["#" * level + " " + text, ""]

    def p(self, text):
        self.lines += [text, ""]

    def table(self, headers, rows, align=None):
        self.lines += [md_table(headers, rows, align), ""]

    def image(self, path, caption):
        self.ctx.pngs.append(Path(path))
        self.lines += [f"![{caption}]({Path(path).name})", "", f"*{caption}*", ""]

    def write(self):
        path = self.ctx.out / "report.md"
        path.write_text("\n".join(self.lines).rstrip() + "\n")
        return path


# ---------------------------------------------------------------------------
# Ours beside the thesis's
# ---------------------------------------------------------------------------

COMPARISON_HEADERS = ["Group", "Model", "Source"] + list(COMPONENT_HEADERS) + ["Frames ok/all"]


def comparison_rows(groups, models, ours, thesis, diff=None, digits=3, counts=None, group_label=str):
    """Rows: per group and model, ours / thesis / ours-to-thesis ratio.

    ours[g][m], thesis[g][m]: tuples (None allowed); diff = (ref_model,
    new_model, thesis_diff[g]) adds "Difference (%)" rows, ours computed as
    100 (ref - new) / ref. counts[g][m] = (ok, all) frames.
    """
    rows = []
    for g in groups:
        first = True
        for m in models:
            o = ours.get(g, {}).get(m)
            t = thesis.get(g, {}).get(m) if thesis else None
            n = len(COMPONENTS)
            o = o or (None,) * n
            t = t or (None,) * n
            cnt = counts[g][m] if counts else None
            cnt_txt = f"{cnt[0]}/{cnt[1]}" if cnt else ""
            rows.append([group_label(g) if first else "", m, "ours"] + [fmt(v, digits) for v in o] + [cnt_txt])
            rows.append(["", "", "thesis"] + [fmt(v, digits) for v in t] + [""])
            rows.append(["", "", "ours/thesis"] + [fmt(ratio(a, b), 2) for a, b in zip(o, t)] + [""])
            first = False
        if diff:
            ref, new, tdiff = diff
            o_ref = ours.get(g, {}).get(ref) or (None,) * 6
            o_new = ours.get(g, {}).get(new) or (None,) * 6
            rows.append(["", "Difference (%)", "ours"] + [fmt(pct_diff(a, b), 2) for a, b in zip(o_ref, o_new)] + [""])
            td = tdiff.get(g) if tdiff else None
            rows.append(["", "", "thesis"] + [fmt(v, 2) for v in (td or (None,) * 6)] + [""])
    return rows


# ---------------------------------------------------------------------------
# Figures shared by the experiments
# ---------------------------------------------------------------------------

def error_series(rows, kind):
    comps = ("x_m", "y_m", "z_m") if kind == "position" else ("roll_deg", "pitch_deg", "yaw_deg")
    labels = ("X", "Y", "Z") if kind == "position" else ("Roll", "Pitch", "Yaw")
    ok = ok_rows(rows)
    return [(lab, [r["range_m"] for r in ok], [r["err_" + c] for r in ok]) for lab, c in zip(labels, comps)]


def error_plots(ctx, rows, stem, what, figure_numbers, guides):
    """Position and orientation error vs range (two PNGs)."""
    out = []
    for kind, unit, fig in (("position", "m", figure_numbers[0]), ("orientation", "deg", figure_numbers[1])):
        path = ctx.out / f"{stem}_{kind}.png"
        plots.scatter_vs_range(path, f"{kind.capitalize()} error, {what} (cf. thesis Figure {fig})",
                               f"error = estimate - truth ({unit})", error_series(rows, kind), guides=guides)
        out.append((path, f"{kind.capitalize()} error versus range, {what} (cf. thesis Figure {fig})"))
    return out


# ---------------------------------------------------------------------------
# Provenance sections and the end of every report
# ---------------------------------------------------------------------------

def commands_section(ctx, rep):
    rep.h("Commands run")
    rep.p("In the repository root, in this order (wall time in seconds; machine-dependent). "
          "\"reused\" marks an analysis done earlier in the same invocation with the same inputs.")
    rows = []
    for step, line, dt in ctx.commands:
        rows.append([step, f"`{line}`" if line else "", fmt(dt, 1) if dt is not None else "reused"])
    rep.table(["Step", "Command", "Wall (s)"], rows, ["---", "---", "---:"])


def software_and_machine(ctx, rep, run_dirs):
    rep.h("Datasets")
    rows = []
    devices = set()
    renderers = set()
    for name in sorted(ctx.datasets_used):
        info = dataset_info(ctx.datasets_used[name])
        if info is None:
            rows.append([name, "missing", "", "", "", ""])
            continue
        fr = info.get("frames")
        ca = info.get("calib")
        rows.append([f"`{rel(ctx.datasets_used[name])}`", f"`{info['manifest_sha256']}`",
                     f"{fr['count']} (x{fr['msaa']}, {info['frame_pairs_listed']} listed)" if fr else "none",
                     f"{ca['count']} (x{ca['msaa']}, {info['calib_pairs_listed']} listed)" if ca else "none",
                     str(info["complete"]).lower(), info["renderer"].get("git", "?")])
        d = info["device"]
        devices.add(f"{d.get('name', '?')}; driver {d.get('driver_name', '?')} {d.get('driver_info', '')}; "
                    f"Vulkan {d.get('api_version', '?')}")
        r = info["renderer"]
        renderers.add(f"{r.get('name', '?')} {r.get('version', '?')} (git {r.get('git', '?')})")
    rep.table(["Dataset", "manifest.json SHA-256", "Frames (MSAA, in manifest)", "Calibration pairs",
               "Complete", "Renderer git"], rows, ["---"] * 6)
    checks = []
    for run_dir in run_dirs:
        run = read_run_json(run_dir)
        checks.append((rel(run_dir), run.get("dataset_manifest_sha256", "?")))
    if checks:
        rep.p("Dataset manifest SHA-256 recorded by each analysis run (`run.json`):")
        rep.table(["Run", "dataset_manifest_sha256"], [[f"`{a}`", f"`{b}`"] for a, b in checks], ["---", "---"])

    rep.h("Software and machine")
    origin = (f" (copies of `{ctx.tools_origin}/renderer/aar-render` and `{ctx.tools_origin}/analyzer/aar-analyze` "
              "made at the start of the invocation)" if ctx.tools_origin else "")
    rows = [
        ["Executables run", f"`{rel(ctx.render)}`, `{rel(ctx.analyze)}`" + origin],
        ["aar-render (from the dataset manifests)", "; ".join(sorted(renderers)) or "n/a"],
        ["Render device (manifest)", "; ".join(sorted(devices)) or "n/a"],
        ["aar-render binary SHA-256 (at its calls)", binary_hashes(ctx, ctx.render)],
        ["aar-analyze", analyzer_version()],
        ["aar-analyze binary SHA-256 (at its calls)", binary_hashes(ctx, ctx.analyze)],
        ["OpenCV (Debian package)", dpkg_version("libopencv-core406") or "n/a"],
        ["Python", platform.python_version()],
        ["matplotlib", matplotlib.__version__],
        ["CPU", cpu_model()],
        ["Cores (os.cpu_count)", str(os.cpu_count())],
        ["OS", f"{platform.system()} {platform.release()}"],
    ]
    rep.table(["Item", "Value"], rows, ["---", "---"])


def finish(ctx, rep):
    path = rep.write()
    missing = [p for p in [path] + ctx.pngs if not p.is_file() or p.stat().st_size == 0]
    if missing:
        raise ExperimentError(f"{ctx.name}: missing outputs: {', '.join(map(str, missing))}")
    LOG(f"{ctx.name}: report {rel(path)} ({len(ctx.pngs)} plots)")
    return path


def conclude(ctx, rep, run_dirs):
    """The end of every report: commands, datasets (with the manifest hashes `run_dirs` recorded),
    software and machine; writes it and returns its path."""
    commands_section(ctx, rep)
    software_and_machine(ctx, rep, run_dirs)
    return finish(ctx, rep)
