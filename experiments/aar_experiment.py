#!/usr/bin/python3
"""Reproduce the experiments of Parsons (AFIT, 2017), chapter IV and Appendix A.

Drives the built tools (aar-render, aar-analyze), reads their CSV/JSON outputs
and writes one report folder per experiment: report.md (our numbers beside the
thesis's, with the ratio ours/thesis), PNG plots, the exact command lines,
dataset manifest hashes, software versions and the machine.

  characterization  thesis Experiment 1: Tables 1-3, Figures 15-19
  conops            thesis Experiment 2: Tables 4-5, Figures 20-24
  msaa              thesis Experiment 3: Tables 6-11, Figures 25-32
  determinism       thesis Appendix A: Figures 33-34
  all               the four, in that order

Datasets are rendered into --datasets (default datasets/) and reused: calling
aar-render again on a dataset skips its verified frames. --quick analyzes a
few frames per region/bin so that `all --quick` runs in a few minutes; its
numbers are a smoke test, not a reproduction.

Only the Python standard library and matplotlib (Debian's python3-matplotlib)
are used. Run from anywhere; commands run in the repository root.
"""

import os
import sys


def _ensure_matplotlib():
    """Re-run under Debian's /usr/bin/python3 when this interpreter lacks matplotlib."""
    try:
        import matplotlib  # noqa: F401
        return
    except ImportError:
        pass
    system_python = "/usr/bin/python3"
    if (os.environ.get("AAR_EXPERIMENT_REEXEC") != "1" and os.path.exists(system_python)
            and os.path.realpath(sys.executable) != os.path.realpath(system_python)):
        os.environ["AAR_EXPERIMENT_REEXEC"] = "1"
        os.execv(system_python, [system_python, os.path.abspath(__file__)] + sys.argv[1:])
    sys.exit("aar_experiment: matplotlib is missing (Debian: apt-get install python3-matplotlib)")


_ensure_matplotlib()

import argparse  # noqa: E402
import csv  # noqa: E402
import hashlib  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import shlex  # noqa: E402
import shutil  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import matplotlib  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import plots  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent

COMPONENTS = ("x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg")
COMPONENT_HEADERS = ("X (m)", "Y (m)", "Z (m)", "Roll (deg)", "Pitch (deg)", "Yaw (deg)")
REGIONS = ("A", "B", "C")
REGION_RANGES = {"A": "70-175 m", "B": "38-70 m", "C": "32-38 m"}
BINS = ("20-60", "60-110")
MSAA_LEVELS = (1, 4, 8, 16, 32)

# ---------------------------------------------------------------------------
# The thesis's numbers: experiments/thesis_tables.json, typed from Parsons
# (2017), chapter IV and Appendices A and B, each number with its table, row
# and column. Component order: X (m), Y (m), Z (m), Roll, Pitch, Yaw (deg).
# None = not reported. "diff" rows are the thesis's printed "Difference (%)"
# rows. Nothing in THESIS is ever used as one of OUR numbers.
# ---------------------------------------------------------------------------
THESIS_TABLES = Path(__file__).resolve().parent / "thesis_tables.json"


def _json_key(key):
    """Row and column keys as the reports index them: [i, j] becomes (i, j); strings and ints stay."""
    return tuple(key) if isinstance(key, list) else key


def load_thesis(path=THESIS_TABLES):
    """{table: nested rows} from thesis_tables.json.

    A row is nested under its `index` keys, in order. Its value: `value` as
    is; else `values`, as a tuple in column order when the columns are names
    (x_m, ..., mean_s, ...), or as {column: value} when they are keys (MSAA
    levels, Q elements).
    """
    with open(path) as f:
        tables = json.load(f)["tables"]
    thesis = {}
    for name, table in tables.items():
        nested = thesis.setdefault(name, {})
        columns = table.get("columns")
        for row in table["rows"]:
            keys = [_json_key(row[k]) for k in table["index"]]
            if "value" in row:
                value = row["value"]
            else:
                if len(row["values"]) != len(columns):
                    raise ValueError(f"{path}: {name}, row {keys}: {len(row['values'])} values for "
                                     f"{len(columns)} columns")
                if all(isinstance(c, str) for c in columns):
                    value = tuple(row["values"])
                else:
                    value = {_json_key(c): v for c, v in zip(columns, row["values"])}
            d = nested
            for k in keys[:-1]:
                d = d.setdefault(k, {})
            if keys[-1] in d:
                raise ValueError(f"{path}: {name}: row {keys} appears twice")
            d[keys[-1]] = value
    return thesis


THESIS = load_thesis()

# Frame selections. None = every frame of the flight path. ("shard", "K/N")
# = frames i with i % N == K, spread over the whole path.
SELECTIONS = {
    "full": {"char": None, "conops": None, "determinism": ("shard", "0/15"), "determinism_runs": 10},
    # char 0/56: 10 frames, 4 in 20-60 m, 5 in 60-110 m; conops 0/61: 10
    # frames, 2 in A, 4 in B, 4 in C.
    "quick": {"char": ("shard", "0/56"), "conops": ("shard", "0/61"),
              "determinism": ("shard", "0/61"), "determinism_runs": 10},
}


class ExperimentError(Exception):
    pass


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------

def rel(path):
    """Path as shown in reports: relative to the repository root when inside it."""
    p = Path(path).resolve()
    try:
        return str(p.relative_to(ROOT))
    except ValueError:
        return str(p)


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def sha256_bytes(data):
    return hashlib.sha256(data).hexdigest()


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


def selection_args(selection):
    if selection is None:
        return []
    kind, value = selection
    return ["--" + kind, value]


def selection_text(selection):
    if selection is None:
        return "all frames"
    return f"frames i with i % {selection[1].split('/')[1]} == {selection[1].split('/')[0]} (--shard {selection[1]})"


def md_table(headers, rows, align=None):
    align = align or (["---"] + ["---:"] * (len(headers) - 1))
    out = ["| " + " | ".join(headers) + " |", "| " + " | ".join(align) + " |"]
    for row in rows:
        out.append("| " + " | ".join(str(c) for c in row) + " |")
    return "\n".join(out)


class Log:
    def __init__(self):
        self.t0 = time.monotonic()

    def __call__(self, msg):
        print(f"[aar_experiment +{time.monotonic() - self.t0:7.1f} s] {msg}", file=sys.stderr, flush=True)


LOG = Log()


# ---------------------------------------------------------------------------
# Running the tools
# ---------------------------------------------------------------------------

class Ctx:
    """One experiment's settings, its command log and the analysis-run cache."""

    def __init__(self, name, args, out, memo):
        self.name = name
        self.build = Path(args.build).resolve()
        self.datasets = Path(args.datasets).resolve()
        self.out = Path(out).resolve()
        self.quick = args.quick
        self.sel = SELECTIONS["quick" if args.quick else "full"]
        self.memo = memo            # shared across experiments of one `all`
        self.commands = []          # (step, command line, seconds or None when reused)
        self.datasets_used = {}     # name -> path
        self.pngs = []
        self.binaries = {}          # tool name -> SHA-256 of the binary at each call
        self.tools_origin = getattr(args, "tools_origin", None)
        self.render = self.build / "renderer" / "aar-render"
        self.analyze = self.build / "analyzer" / "aar-analyze"

    def env(self):
        env = dict(os.environ)
        # The tools read Slurm array variables as a default shard: never here.
        for key in list(env):
            if key.startswith("SLURM_ARRAY_TASK_"):
                del env[key]
        return env

    def run(self, step, argv):
        line = " ".join(shlex.quote(rel(a) if isinstance(a, Path) else str(a)) for a in argv)
        LOG(f"{self.name}: {step}\n    $ {line}")
        tool = Path(argv[0])
        self.binaries.setdefault(tool.name, set()).add(sha256_file(tool))
        t = time.monotonic()
        returncode = subprocess.run([str(a) for a in argv], cwd=ROOT, env=self.env(),
                                    stdout=sys.stderr, stderr=sys.stderr).returncode
        dt = time.monotonic() - t
        self.commands.append((step, line, dt))
        if returncode != 0:
            raise ExperimentError(f"{self.name}: step '{step}' failed with exit status {returncode}: {line}")
        LOG(f"{self.name}: {step}: done in {dt:.1f} s")
        return dt

    def dataset(self, name):
        path = self.datasets / name
        self.datasets_used[name] = path
        return path


def _other_renders_into(dataset):
    """PIDs of running aar-render processes (not ours) that write into `dataset`."""
    target = os.path.realpath(dataset)
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                argv = [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
            cwd = os.readlink(f"/proc/{entry}/cwd")
        except OSError:
            continue
        if not argv or os.path.basename(argv[0]) != "aar-render":
            continue
        if any(os.path.realpath(os.path.join(cwd, a)) == target for a in argv[1:]):
            found.append(int(entry))
    return found


def wait_for_other_renders(ctx, dataset):
    waited = False
    while True:
        pids = _other_renders_into(dataset)
        if not pids:
            if waited:
                LOG(f"{ctx.name}: the other render into {rel(dataset)} has finished")
            return
        if not waited:
            LOG(f"{ctx.name}: aar-render (pid {', '.join(map(str, pids))}) is writing into {rel(dataset)}; "
                "waiting for it to finish")
            waited = True
        time.sleep(10)


def _render(ctx, step, argv, dataset):
    """Renders into `dataset`; aar-render resumes, skipping verified pairs."""
    wait_for_other_renders(ctx, dataset)
    ctx.run(step, argv)


def render_calib(ctx, dataset, msaa):
    _render(ctx, f"render calibration boards into {dataset.name} (x{msaa})",
            [ctx.render, "calib", dataset, "--msaa", msaa], dataset)


def render_frames(ctx, dataset, msaa, flight_path, selection):
    argv = [ctx.render, "render", dataset, "--msaa", msaa, "--flight-path", flight_path]
    _render(ctx, f"render {flight_path} into {dataset.name} (x{msaa}, {selection_text(selection)})",
            argv + selection_args(selection), dataset)


def calibrate(ctx, dataset, out):
    key = ("calibrate", str(dataset))
    if key in ctx.memo and (Path(ctx.memo[key]) / "calibration_report.json").exists():
        ctx.commands.append((f"calibrate {dataset.name} (reused: {rel(ctx.memo[key])})", "", None))
        return Path(ctx.memo[key])
    if out.exists():
        shutil.rmtree(out)
    ctx.run(f"calibrate {dataset.name}", [ctx.analyze, "calibrate", dataset, "--out", out])
    for name in ("calibration.yaml", "calibration_report.json"):
        if not (out / name).is_file():
            raise ExperimentError(f"{ctx.name}: aar-analyze calibrate wrote no {out / name}")
    ctx.memo[key] = str(out)
    return out


def analyze(ctx, run_name, dataset, model, selection, calibration=None, reuse=True, label="", extra=()):
    """aar-analyze run; the same inputs within one invocation reuse the earlier run."""
    key = ("run", str(dataset), model, repr(selection), str(calibration), tuple(extra))
    if reuse and key in ctx.memo:
        ctx.commands.append((f"analyze {dataset.name} with the {model} model (reused: {rel(ctx.memo[key])})", "", None))
        return Path(ctx.memo[key])
    out = ctx.out / "runs" / run_name
    if out.exists():
        shutil.rmtree(out)
    argv = [ctx.analyze, "run", dataset, "--model", model, "--icp-iterations", "30"]
    if calibration is not None:
        argv += ["--calibration", calibration]
    argv += list(extra) + selection_args(selection) + ["--out", out]
    ctx.run(f"analyze {dataset.name} with the {model} model" + (f" ({' '.join(extra)})" if extra else "")
            + (f", calibration {rel(calibration)}" if calibration else "")
            + f" ({selection_text(selection)}){label}", argv)
    for name in ("frames.csv", "summary.json", "run.json"):
        if not (out / name).is_file():
            raise ExperimentError(f"{ctx.name}: aar-analyze run wrote no {out / name}")
    if reuse:
        ctx.memo[key] = str(out)
    return out


# ---------------------------------------------------------------------------
# Reading the tools' outputs
# ---------------------------------------------------------------------------

# The thesis's shelled-model argument (section 4.1: the full model's surfaces
# that the cameras never see hurt the registration) holds for ICP that pairs
# every MODEL point with its nearest sensed point. Experiments 1 and 2 are
# therefore run with the analyzer's default pairing and again with that one.
THESIS_PAIRING = ("--correspondence", "model_to_sensed")


def pairing_of(run_dir):
    """ICP pairing direction a run used, from its run.json."""
    return read_json(run_dir / "run.json").get("options", {}).get("icp", {}).get("correspondence", "?")


def read_frames(run_dir):
    rows = []
    with open(run_dir / "frames.csv", newline="") as f:
        for r in csv.DictReader(f):
            row = {"frame": int(r["frame"]), "region": r["region"], "status": r["status"],
                   "range_m": float(r["range_m"])}
            for k, v in r.items():
                if k.startswith(("err_", "est_", "truth_", "ms_")) or k in ("sensed_points", "icp_rmse_m"):
                    row[k] = float(v) if v not in ("", None) else None
            rows.append(row)
    return rows


def ok_rows(rows):
    return [r for r in rows if r["status"] == "ok"]


def read_json(path):
    with open(path) as f:
        return json.load(f)


def group_stats(summary, model, group, kind):
    """summary.json models.<model>.<group>.<kind> as a tuple in COMPONENTS order (None if absent)."""
    g = summary["models"][model][group]
    values = g.get(kind)
    if values is None:
        return None
    return tuple(values[c] for c in COMPONENTS)


def group_counts(summary, model, group):
    g = summary["models"][model][group]
    return g["ok"], g["frames"]


def sidecar(dataset, frame):
    return read_json(dataset / "frames" / f"{frame:06d}.json")


def dataset_info(path):
    manifest_path = path / "manifest.json"
    if not manifest_path.is_file():
        return None
    m = read_json(manifest_path)
    info = {"manifest_sha256": sha256_file(manifest_path), "renderer": m.get("renderer", {}),
            "device": m.get("device", {}), "complete": m.get("complete")}
    for section in ("frames", "calib"):
        s = m.get(section)
        if s:
            info[section] = {"count": s.get("count"), "msaa": s.get("msaa", {}).get("level"),
                             "method": s.get("msaa", {}).get("method"),
                             "passes": s.get("msaa", {}).get("passes")}
    files = m.get("files", {})
    info["frame_pairs_listed"] = sum(1 for k in files if k.startswith("frames/") and k.endswith(".json"))
    info["calib_pairs_listed"] = sum(1 for k in files if k.startswith("calib/") and k.endswith(".json"))
    info["calib_files"] = {k: v for k, v in files.items() if k.startswith("calib/")}
    return info


def summary_without_timing(path):
    s = read_json(path)
    s.pop("timing", None)
    return json.dumps(s, sort_keys=True, indent=1).encode()


def frames_csv_without_timing(path):
    """frames.csv with the ms_* columns (the last six) removed, as bytes."""
    out = []
    with open(path, newline="") as f:
        for line in f.read().splitlines():
            out.append(",".join(line.split(",")[:28]))
    return ("\n".join(out) + "\n").encode()


# ---------------------------------------------------------------------------
# Report building
# ---------------------------------------------------------------------------

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


COMPARISON_HEADERS = ["Group", "Model", "Source"] + list(COMPONENT_HEADERS) + ["Frames ok/all"]


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
        run = read_json(run_dir / "run.json")
        checks.append((rel(run_dir), run.get("dataset_manifest_sha256", "?")))
    if checks:
        rep.p("Dataset manifest SHA-256 recorded by each analysis run (`run.json`):")
        rep.table(["Run", "dataset_manifest_sha256"], [[f"`{a}`", f"`{b}`"] for a, b in checks], ["---", "---"])

    rep.h("Software and machine")
    analyzer_version = _analyzer_version()
    origin = (f" (copies of `{ctx.tools_origin}/renderer/aar-render` and `{ctx.tools_origin}/analyzer/aar-analyze` "
              "made at the start of the invocation)" if ctx.tools_origin else "")
    rows = [
        ["Executables run", f"`{rel(ctx.render)}`, `{rel(ctx.analyze)}`" + origin],
        ["aar-render (from the dataset manifests)", "; ".join(sorted(renderers)) or "n/a"],
        ["Render device (manifest)", "; ".join(sorted(devices)) or "n/a"],
        ["aar-render binary SHA-256 (at its calls)", _binary_hashes(ctx, ctx.render)],
        ["aar-analyze", analyzer_version],
        ["aar-analyze binary SHA-256 (at its calls)", _binary_hashes(ctx, ctx.analyze)],
        ["OpenCV (Debian package)", _dpkg_version("libopencv-core406") or "n/a"],
        ["Python", platform.python_version()],
        ["matplotlib", matplotlib.__version__],
        ["CPU", _cpu_model()],
        ["Cores (os.cpu_count)", str(os.cpu_count())],
        ["OS", f"{platform.system()} {platform.release()}"],
    ]
    rep.table(["Item", "Value"], rows, ["---", "---"])


def _binary_hashes(ctx, tool):
    hashes = sorted(ctx.binaries.get(Path(tool).name, set()))
    if not hashes:
        return f"`{sha256_file(tool)}` (not called in this experiment)"
    text = ", ".join(f"`{h}`" for h in hashes)
    if len(hashes) > 1:
        text += " (**the binary changed during the experiment**: it was rebuilt meanwhile)"
    return text


_ANALYZER_VERSION = None


def _analyzer_version():
    # run.json carries no analyzer version; the source tree's commit when the
    # invocation started is the closest identification (plus the binary's hash).
    global _ANALYZER_VERSION
    if _ANALYZER_VERSION is None:
        _ANALYZER_VERSION = _source_tree_version()
    return _ANALYZER_VERSION


def _source_tree_version():
    try:
        head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short=12", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "analyzer", "common"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return (f"source tree HEAD {head} at the start" + (" with uncommitted changes in analyzer/ or common/"
                                                            if dirty else "")
                + " (run.json records no analyzer version)")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (run.json records no analyzer version; not a git checkout)"


def _dpkg_version(package):
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", package],
                             capture_output=True, text=True)
        return out.stdout.strip() or None
    except OSError:
        return None


def _cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def commands_section(ctx, rep):
    rep.h("Commands run")
    rep.p("In the repository root, in this order (wall time in seconds; machine-dependent). "
          "\"reused\" marks an analysis done earlier in the same invocation with the same inputs.")
    rows = []
    for step, line, dt in ctx.commands:
        rows.append([step, f"`{line}`" if line else "", fmt(dt, 1) if dt is not None else "reused"])
    rep.table(["Step", "Command", "Wall (s)"], rows, ["---", "---", "---:"])


def finish(ctx, rep):
    path = rep.write()
    missing = [p for p in [path] + ctx.pngs if not p.is_file() or p.stat().st_size == 0]
    if missing:
        raise ExperimentError(f"{ctx.name}: missing outputs: {', '.join(map(str, missing))}")
    LOG(f"{ctx.name}: report {rel(path)} ({len(ctx.pngs)} plots)")
    return path


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


def mean_abs(values):
    values = [abs(v) for v in values if v is not None]
    return sum(values) / len(values) if values else None


# ---------------------------------------------------------------------------
# Experiment 1: characterization
# ---------------------------------------------------------------------------

def char_tables(rep, summaries, note):
    """Tables 1-3 (thesis layout) from {model: summary.json}."""
    def stats(kind):
        return {b: {"Full Model": group_stats(summaries["full"], "full", b, kind),
                    "Shelled Model": group_stats(summaries["shelled"], "shelled", b, kind)} for b in BINS}

    counts = {b: {"Full Model": group_counts(summaries["full"], "full", b),
                  "Shelled Model": group_counts(summaries["shelled"], "shelled", b)} for b in BINS}
    models = ("Full Model", "Shelled Model")

    def thesis_tab(tab):
        return {b: {"Full Model": THESIS[tab][b]["full"], "Shelled Model": THESIS[tab][b]["shelled"]} for b in BINS}

    rep.h(f"Table 1: mean absolute 6DOF error{note}", 3)
    rep.table(COMPARISON_HEADERS, comparison_rows(
        BINS, models, stats("mean_abs_error"), thesis_tab("table1"),
        diff=("Full Model", "Shelled Model", {b: THESIS["table1"][b]["diff"] for b in BINS}),
        counts=counts, group_label=lambda b: f"{b} m"))
    rep.h(f"Table 2: RMS 6DOF error{note}", 3)
    rep.table(COMPARISON_HEADERS, comparison_rows(
        BINS, models, stats("rms_error"), thesis_tab("table2"), counts=counts, group_label=lambda b: f"{b} m"))

    rep.h(f"Table 3: ICP execution time{note} (machine-dependent)", 3)
    rep.p("From `summary.json` `timing.<model>.<bin>` (`icp_ms_mean`, `icp_ms_std`: sample standard deviation), "
          "converted to seconds. Ours: one core of the machine below, C++ with a KD-tree; the thesis's: its own "
          "implementation and machine, so the ratio compares implementations as much as models. Difference (%) "
          "= 100 (full - shelled) / full; the thesis reports 87 % (20-60 m) and 78 % (60-110 m), and a standard "
          "deviation 28 and 17 times lower with the shelled model.")
    rows = []
    for b in BINS:
        vals = {}
        for m in ("full", "shelled"):
            t = summaries[m]["timing"][m][b]
            mean = t["icp_ms_mean"] / 1000.0 if t["icp_ms_mean"] is not None else None
            std = t["icp_ms_std"] / 1000.0 if t["icp_ms_std"] is not None else None
            vals[m] = (mean, std)
            tm, ts = THESIS["table3"][b][m]
            label = "Full Model" if m == "full" else "Shelled Model"
            rows.append([f"{b} m" if m == "full" else "", label, fmt(mean, 4), fmt(tm, 4), fmt(ratio(mean, tm), 3),
                         fmt(std, 4), fmt(ts, 4), fmt(ratio(std, ts), 3)])
        tf, tsh = THESIS["table3"][b]["full"], THESIS["table3"][b]["shelled"]
        rows.append(["", "Difference (%) / std full:shelled", fmt(pct_diff(vals["full"][0], vals["shelled"][0]), 1),
                     fmt(pct_diff(tf[0], tsh[0]), 1), "",
                     fmt(ratio(vals["full"][1], vals["shelled"][1]), 1) + "x", fmt(tf[1] / tsh[1], 1) + "x", ""])
    rep.table(["Range", "Model", "Mean ICP (s) ours", "thesis", "ours/thesis", "Std (s) ours", "thesis",
               "ours/thesis"], rows)


def exp_characterization(ctx):
    ds = ctx.dataset("char-x16")
    sel = ctx.sel["char"]
    render_calib(ctx, ds, 16)
    render_frames(ctx, ds, 16, "flightpaths/characterization.csv", sel)
    runs = {m: analyze(ctx, f"char-x16-{m}", ds, m, sel) for m in ("shelled", "full")}
    runs_tp = {m: analyze(ctx, f"char-x16-{m}-model-to-sensed", ds, m, sel, extra=THESIS_PAIRING)
               for m in ("shelled", "full")}
    summaries = {m: read_json(runs[m] / "summary.json") for m in runs}
    summaries_tp = {m: read_json(runs_tp[m] / "summary.json") for m in runs_tp}
    frames = {m: read_frames(runs[m]) for m in runs}
    pairing = pairing_of(runs["shelled"])

    rep = Report(ctx, "Experiment 1: ICP characterization, shelled versus full reference model")
    rep.p("Thesis section 4.1 (Tables 1-3, Figures 15-19). The receiver is rendered at every position of "
          f"`flightpaths/characterization.csv` (558 positions, 10-110 m, zero attitude) with MSAA x16; "
          f"analyzed: {selection_text(sel)}. Both reference models, at most 30 ICP iterations, ICP seeded at the "
          "sensed cloud's centroid with zero attitude (the thesis's seeding), calibration from the dataset's own "
          "x16 board images. Our numbers come from each run's `summary.json` (statistics) and `frames.csv` "
          "(plots); the thesis's are typed from its tables. Difference (%) = 100 (full - shelled) / full, "
          "positive when the shelled model is better (the thesis's definition). Frames the analyzer could not "
          "measure (its ICP failure test, docs/analysis.md) are left out of its statistics; \"Frames ok/all\" "
          "counts them.")
    rep.p(f"Two ICP pairing directions are reported: the analyzer's default (`{pairing}`, from `run.json`), and "
          "`model_to_sensed` (every reference-model point paired with its nearest sensed point), under which "
          "model surfaces the cameras do not see pull the estimate, which is the effect the thesis's shelled "
          "model removes (section 4.1). The thesis does not name its pairing direction.")

    rep.h(f"With the analyzer's default ICP pairing (`{pairing}`)")
    char_tables(rep, summaries, f" ({pairing})")
    rep.h(f"With the model-to-sensed ICP pairing (`{pairing_of(runs_tp['shelled'])}`)")
    char_tables(rep, summaries_tp, f" ({pairing_of(runs_tp['shelled'])})")

    rep.h(f"Registration details per range bin (ours, {pairing})")
    rows = []
    for b in BINS:
        for m in ("full", "shelled"):
            g = summaries[m]["models"][m][b]
            rows.append([f"{b} m", m, f"{g['ok']}/{g['frames']}", fmt(g.get("sensed_points_mean"), 0),
                         fmt(g.get("icp_iterations_mean"), 1), str(g.get("icp_converged")),
                         fmt(g.get("icp_rmse_m_mean"), 3)])
    rep.table(["Range", "Model", "Frames ok/all", "Sensed points (mean)", "ICP iterations (mean)",
               "Converged before 30", "ICP RMSE (m, mean)"], rows)

    # Below 20 m (no thesis bin) and partial visibility, from frames.csv and the sidecars.
    rep.h("Partial visibility (positions closer than the box fits the view)")
    vis = []
    for r in ok_rows(frames["shelled"]):
        sc = sidecar(ds, r["frame"])
        vis.append((r["frame"], r["range_m"], min(sc["in_view"]["left"], sc["in_view"]["right"])))
    partial = [v for v in vis if v[2] < 1.0]
    if partial:
        lo = min(v[1] for v in partial)
        hi = max(v[1] for v in partial)
        pf = {v[0] for v in partial}
        rows = []
        for m in ("full", "shelled"):
            part = [r for r in ok_rows(frames[m]) if r["frame"] in pf]
            full_view = [r for r in ok_rows(frames[m]) if r["frame"] not in pf and r["range_m"] < 60.0]
            for label, sub in (("partly out of view", part), ("fully in view, < 60 m", full_view)):
                rows.append([m, label, str(len(sub))] + [fmt(mean_abs([r["err_" + c] for r in sub]), 3)
                                                         for c in COMPONENTS])
        rep.p(f"{len(partial)} analyzed positions have part of the receiver outside an image (sidecar `in_view` "
              f"< 1 in the left or right camera), at {lo:.1f}-{hi:.1f} m; the smallest visible fraction is "
              f"{min(v[2] for v in partial):.3f}. Mean absolute error there (from `frames.csv`), against the fully "
              "visible positions closer than 60 m:")
        rep.table(["Model", "Positions", "Frames"] + list(COMPONENT_HEADERS), rows)
    else:
        rep.p(f"None of the {len(vis)} analyzed positions has the receiver partly outside an image "
              "(sidecar `in_view` = 1 in both cameras).")

    # Plots (Figures 15-19).
    rep.h("Figures")
    for m, figs in (("full", (15, 17)), ("shelled", (16, 18))):
        for path, cap in error_plots(ctx, frames[m], f"char_{m}", f"{m} reference model, {pairing} pairing, "
                                     "characterization",
                                     figs, "bins"):
            rep.image(path, cap)
    for stem, rdirs in (("char_icp_time", runs), ("char_icp_time_model_to_sensed", runs_tp)):
        path = ctx.out / f"{stem}.png"
        p_name = pairing_of(rdirs["shelled"])
        series = []
        for m in ("full", "shelled"):
            ok = ok_rows(read_frames(rdirs[m]))
            series.append((f"{m} model", [r["range_m"] for r in ok], [r["ms_icp"] / 1000.0 for r in ok]))
        plots.scatter_vs_range(path, f"ICP execution time per position, {p_name} pairing "
                                     "(cf. thesis Figure 19; machine-dependent)",
                               "ICP time (s)", series, guides="bins", zero_line=False)
        rep.image(path, f"ICP execution time versus range, both models, {p_name} pairing (cf. thesis Figure 19)")

    commands_section(ctx, rep)
    software_and_machine(ctx, rep, [runs["shelled"], runs["full"], runs_tp["shelled"], runs_tp["full"]])
    return finish(ctx, rep)


# ---------------------------------------------------------------------------
# Experiment 2: CONOPS flight path
# ---------------------------------------------------------------------------

def region_table_data(summaries, key_model, kind):
    """{region: {label: tuple}} from {label: (summary, model)}."""
    return {g: {label: group_stats(s, m, g, kind) for label, (s, m) in key_model.items()} for g in REGIONS}


def region_counts(key_model):
    return {g: {label: group_counts(s, m, g) for label, (s, m) in key_model.items()} for g in REGIONS}


def conops_tables(rep, summaries, note):
    """Tables 4-5 (thesis layout) from {model: summary.json}."""
    km = {"Full Model": (summaries["full"], "full"), "Shelled Model": (summaries["shelled"], "shelled")}
    models = ("Full Model", "Shelled Model")

    def thesis_tab(tab):
        return {g: {"Full Model": THESIS[tab][g]["full"], "Shelled Model": THESIS[tab][g]["shelled"]}
                for g in REGIONS}

    counts = region_counts(km)
    rep.h(f"Table 4: mean absolute 6DOF error per region{note}", 3)
    rep.table(COMPARISON_HEADERS, comparison_rows(
        REGIONS, models, region_table_data(summaries, km, "mean_abs_error"), thesis_tab("table4"),
        diff=("Full Model", "Shelled Model", {g: THESIS["table4"][g]["diff"] for g in REGIONS}),
        counts=counts, group_label=lambda g: f"Region {g} ({REGION_RANGES[g]})"))
    rep.h(f"Table 5: RMS 6DOF error per region{note}", 3)
    rep.table(COMPARISON_HEADERS, comparison_rows(
        REGIONS, models, region_table_data(summaries, km, "rms_error"), thesis_tab("table5"),
        counts=counts, group_label=lambda g: f"Region {g} ({REGION_RANGES[g]})"))


def exp_conops(ctx):
    ds = ctx.dataset("conops-x16")
    sel = ctx.sel["conops"]
    render_calib(ctx, ds, 16)
    render_frames(ctx, ds, 16, "flightpaths/conops.csv", sel)
    runs = {m: analyze(ctx, f"conops-x16-{m}", ds, m, sel) for m in ("shelled", "full")}
    runs_tp = {m: analyze(ctx, f"conops-x16-{m}-model-to-sensed", ds, m, sel, extra=THESIS_PAIRING)
               for m in ("shelled", "full")}
    summaries = {m: read_json(runs[m] / "summary.json") for m in runs}
    summaries_tp = {m: read_json(runs_tp[m] / "summary.json") for m in runs_tp}
    frames = {m: read_frames(runs[m]) for m in runs}
    pairing = pairing_of(runs["shelled"])
    pairing_tp = pairing_of(runs_tp["shelled"])

    rep = Report(ctx, "Experiment 2: CONOPS flight path, shelled versus full reference model")
    rep.p("Thesis section 4.2 (Tables 4-5, Figures 20-24). `flightpaths/conops.csv` (609 samples, 175 m to the "
          f"contact position at 32 m, attitude up to 2.8 deg) rendered with MSAA x16; analyzed: "
          f"{selection_text(sel)}. At most 30 ICP iterations, centroid seed, calibration from the dataset's own x16 "
          "boards. Regions: A 70-175 m, B 38-70 m, C 32-38 m. The thesis reports only position for region A "
          "(\"orientation values in region A ... were inconsistent\"). Difference (%) = 100 (full - shelled) / full. "
          "Frames the analyzer could not measure are left out of its statistics (\"Frames ok/all\").")
    rep.p(f"As in Experiment 1, the analyzer's default ICP pairing (`{pairing}`) and the model-to-sensed pairing "
          f"(`{pairing_tp}`), under which unseen model surfaces pull the estimate, are both reported.")
    rep.h(f"With the analyzer's default ICP pairing (`{pairing}`)")
    conops_tables(rep, summaries, f" ({pairing})")
    rep.h(f"With the model-to-sensed ICP pairing (`{pairing_tp}`)")
    conops_tables(rep, summaries_tp, f" ({pairing_tp})")

    rep.h(f"Registration details per region (ours, {pairing})")
    rows = []
    for g in REGIONS:
        for m in ("full", "shelled"):
            s = summaries[m]["models"][m][g]
            t = summaries[m]["timing"][m][g]
            rows.append([g, m, f"{s['ok']}/{s['frames']}", fmt(s.get("sensed_points_mean"), 0),
                         fmt(s.get("icp_iterations_mean"), 1), fmt(s.get("icp_rmse_m_mean"), 3),
                         fmt(t["icp_ms_mean"], 1)])
    rep.table(["Region", "Model", "Frames ok/all", "Sensed points (mean)", "ICP iterations (mean)",
               "ICP RMSE (m, mean)", "ICP time (ms, mean; machine-dependent)"], rows)

    # Partial visibility (thesis Figure 24: the tail leaves the view at 38-42 m).
    rep.h("Partial visibility (cf. thesis Figure 24)")
    vis = []
    for r in frames["shelled"]:
        sc = sidecar(ds, r["frame"])
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
    band = (38.0, 42.0)
    rows = []
    pf = {v[0] for v in partial}
    for m in ("full", "shelled"):
        ok = ok_rows(frames[m])
        subsets = [(f"{band[0]:.0f}-{band[1]:.0f} m", [r for r in ok if band[0] <= r["range_m"] < band[1]]),
                   ("rest of region B", [r for r in ok if r["region"] == "B"
                                         and not band[0] <= r["range_m"] < band[1]])]
        if partial:
            subsets.append(("partly out of view", [r for r in ok if r["frame"] in pf]))
        for label, sub in subsets:
            rows.append([m, label, str(len(sub))] + [fmt(mean_abs([r["err_" + c] for r in sub]), 3)
                                                     for c in COMPONENTS])
    rep.table(["Model", "Frames", "Count"] + [f"mean abs {h}" for h in COMPONENT_HEADERS], rows)

    rep.h("Figures")
    for m, figs in (("shelled", (20, 21)), ("full", (22, 23))):
        for path, cap in error_plots(ctx, frames[m], f"conops_{m}", f"{m} reference model, {pairing} pairing, "
                                     "CONOPS path",
                                     figs, "regions"):
            rep.image(path, cap)
    path = ctx.out / "conops_visibility.png"
    ok = ok_rows(frames["shelled"])
    norm = [math.sqrt(r["err_x_m"] ** 2 + r["err_y_m"] ** 2 + r["err_z_m"] ** 2) for r in ok]
    plots.panels_vs_range(
        path, "Receiver visibility and position error on the CONOPS path (cf. thesis Figure 24)",
        [("fraction of receiver\nvertices in view (sidecar)",
          [("left camera", [v[1] for v in vis], [v[2] for v in vis]),
           ("right camera", [v[1] for v in vis], [v[3] for v in vis])], (0.0, 1.08)),
         ("position error norm (m)\nshelled model", [("|estimate - truth|", [r["range_m"] for r in ok], norm)])],
        guides="regions", shade=(band[0], band[1], "thesis: tail out of view"))
    rep.image(path, "Visible fraction of the receiver (sidecar in_view) and shelled position error versus range "
                    "(cf. thesis Figure 24)")

    commands_section(ctx, rep)
    software_and_machine(ctx, rep, [runs["shelled"], runs["full"], runs_tp["shelled"], runs_tp["full"]])
    return finish(ctx, rep)


# ---------------------------------------------------------------------------
# Experiment 3: MSAA
# ---------------------------------------------------------------------------

def exp_msaa(ctx):
    cal = {}
    reports = {}
    for level in MSAA_LEVELS:
        ds = ctx.dataset(f"calib-x{level}")
        render_calib(ctx, ds, level)
        cal[level] = calibrate(ctx, ds, ctx.out / "calibrations" / f"x{level}")
        reports[level] = read_json(cal[level] / "calibration_report.json")

    sel = ctx.sel["conops"]
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
    summaries = {k: read_json(v / "summary.json") for k, v in runs.items()}
    frames = {k: read_frames(v) for k, v in runs.items()}
    labels = {"msaa": "MSAA", "calib": "MSAA Calib", "none": "No MSAA"}

    rep = Report(ctx, "Experiment 3: effect of MSAA on calibration and pose estimation")
    rep.p("Thesis section 4.3 and Appendix B (Tables 6-11, Figures 25-32). The calibration board is rendered "
          "at its 12 poses (`aar-render calib`, the thesis used 10) at MSAA x1, x4, x8, x16 and x32 into separate "
          "datasets and calibrated with `aar-analyze calibrate` (OpenCV: chessboard corners + cornerSubPix, "
          "calibrateCamera, stereoCalibrate, stereoRectify; distortion fixed at zero, the renderer has none). "
          "x1 is a single sample per pixel (the thesis's \"No MSAA\"); x8, x16 and x32 are composed of jittered "
          "passes of the device's native x4 (see the manifests).")

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

    rep.h("Table 7: element-wise percent error of Q against the ideal Q")
    rep.p("`100 |q - q_ideal| / |q_ideal|` (0 where the ideal element is 0), from `versus_ideal.q_percent_error`. "
          "Q = [[1,0,0,-cx],[0,1,0,-cy],[0,0,0,f],[0,0,1/b,0]] after rectification, so the four non-zero "
          "elements are the rectified principal point (cx, cy), the focal length and the inverse baseline. "
          "Every other element is 0 in both sources. Note: stereoRectify (CALIB_ZERO_DISPARITY, alpha -1) moves "
          "the rectified principal point when the two estimated cameras differ, so Q[0][3] measures the "
          "rectification as much as the intrinsics.")
    rows = []
    for (i, j), name in (((0, 3), "Q[0][3] = -cx"), ((1, 3), "Q[1][3] = -cy"), ((2, 3), "Q[2][3] = f"),
                         ((3, 2), "Q[3][2] = 1/b")):
        row = [name]
        for lv in (1, 16):
            o = reports[lv]["versus_ideal"]["q_percent_error"][i][j]
            t = THESIS["table7"][lv][(i, j)]
            row += [fmt(o, 3), fmt(t, 3), fmt(ratio(o, t), 2)]
        rows.append(row)
    others = max(reports[lv]["versus_ideal"]["q_percent_error"][i][j] for lv in (1, 16) for i in range(4)
                 for j in range(4) if (i, j) not in ((0, 3), (1, 3), (2, 3), (3, 2)))
    rep.table(["Element", "No MSAA Q ours (%)", "thesis (%)", "ours/thesis", "MSAAx16 Q ours (%)", "thesis (%)",
               "ours/thesis"], rows)
    rep.p(f"Largest percent error of any other element (ours, x1 and x16): {fmt(others, 6)}.")
    for lv in (1, 16):
        q = reports[lv]["versus_ideal"]["q_percent_error"]
        rep.p(f"Full 4x4 percent-error matrix, x{lv} (ours):")
        rep.table(["", "col 0", "col 1", "col 2", "col 3"],
                  [[f"row {i}"] + [fmt(q[i][j], 4) for j in range(4)] for i in range(4)])

    # Cross-check: the conops datasets' own calibrations equal the separate calib-x1 / calib-x16 ones.
    rows = []
    for key, lv in (("none", 1), ("msaa", 16)):
        a = sha256_file(runs[key] / "calibration.yaml")
        b = sha256_file(cal[lv] / "calibration.yaml")
        rows.append([labels[key], f"calib-x{lv}", "identical" if a == b else "DIFFERENT", f"`{a[:16]}`",
                     f"`{b[:16]}`"])
    rows.append([labels["calib"], "calib-x16 (via --calibration)",
                 "identical" if sha256_file(runs["calib"] / "calibration.yaml")
                 == sha256_file(cal[16] / "calibration.yaml") else "DIFFERENT", "", ""])
    rep.p("Calibration used by each flight-path run against the stand-alone calibration of the same MSAA level "
          "(SHA-256 of calibration.yaml; identical board images give identical calibrations):")
    rep.table(["Flight run", "Stand-alone calibration", "calibration.yaml", "run (SHA-256 prefix)",
               "stand-alone (SHA-256 prefix)"], rows, ["---"] * 5)

    rep.h("Flight path with and without MSAA (Tables 8-11)")
    rep.p(f"CONOPS path, shelled model, 30 ICP iterations, `{pairing_of(runs['none'])}` ICP pairing (the "
          "analyzer's default), " + selection_text(sel) + ". "
          f"**No MSAA**: imagery x1 (`{rel(ds1)}`) and its own x1 calibration. **MSAA Calib** (the "
          "thesis's \"partial MSAA\"): imagery x1 with `--calibration` from the x16 calibration. **MSAA**: imagery "
          f"x16 (`{rel(ds16)}`) and its own x16 calibration. The thesis reports region A orientation "
          "here (unlike Table 4). Difference (%) as in the thesis: Table 8 = 100 (No MSAA - MSAA Calib) / No MSAA, "
          "Table 9 = 100 (MSAA Calib - MSAA) / MSAA Calib, Table 10 = 100 (No MSAA - MSAA) / No MSAA.")
    km = {labels[k]: (summaries[k], "shelled") for k in ("msaa", "calib", "none")}
    mean = region_table_data(summaries, km, "mean_abs_error")
    rms = region_table_data(summaries, km, "rms_error")
    counts = region_counts(km)
    th_mean = {g: {labels[k]: THESIS["mean_abs"][k][g] for k in labels} for g in REGIONS}
    th_rms = {g: {labels[k]: THESIS["table11"][k][g] for k in labels} for g in REGIONS}
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
        series.append((labels[key], [r["range_m"] for r in ok], [r["err_y_m"] for r in ok]))
    plots.scatter_vs_range(path, "Y error on the CONOPS path, the three MSAA configurations (cf. thesis Figure 30)",
                           "Y error (m)", series, guides="regions")
    rep.image(path, "Y (lateral) error versus range for no MSAA, MSAA calibration only and MSAA "
                    "(cf. thesis Figure 30, which shows the Y error as point clouds)")

    commands_section(ctx, rep)
    software_and_machine(ctx, rep, [runs["none"], runs["calib"], runs["msaa"]])
    return finish(ctx, rep)


# ---------------------------------------------------------------------------
# Appendix A: determinism
# ---------------------------------------------------------------------------

def exp_determinism(ctx):
    ds = ctx.dataset("conops-x16")
    sel = ctx.sel["determinism"]
    n_runs = ctx.sel["determinism_runs"]
    render_calib(ctx, ds, 16)
    render_frames(ctx, ds, 16, "flightpaths/conops.csv", sel)
    run_dirs = [analyze(ctx, f"det-{k:02d}", ds, "shelled", sel, reuse=False,
                        label=f", run {k} of {n_runs}") for k in range(1, n_runs + 1)]
    frames = [read_frames(d) for d in run_dirs]

    rep = Report(ctx, "Appendix A: determinism of the analysis")
    rep.p(f"The shelled-model analysis of the same {len(frames[0])} CONOPS frames (`{rel(ds)}`, "
          f"{selection_text(sel)}, spread over regions A, B and C; analyzer defaults, `{pairing_of(run_dirs[0])}` "
          f"ICP pairing) is run {n_runs} times, each run from scratch "
          "(calibration, reference model, every frame). The thesis (Appendix A, Figures 33-34) saw a standard "
          "deviation of up to 5 cm in position (one outlier at ~150 m; below 2.5 cm closer than 50 m) and up to "
          "0.4 deg in orientation across 10 estimations, because OpenCV's disparity and its point sub-sampling "
          "were not deterministic in its pipeline.")

    per_frame = {}
    for run in frames:
        for r in run:
            per_frame.setdefault(r["frame"], []).append(r)
    regions_count = {}
    for f, rs in per_frame.items():
        regions_count[rs[0]["region"]] = regions_count.get(rs[0]["region"], 0) + 1
    rows = []
    stds = {c: {} for c in COMPONENTS}
    for c in COMPONENTS:
        for f, rs in sorted(per_frame.items()):
            vals = [r["est_" + c] for r in rs if r["status"] == "ok"]
            if len(vals) != n_runs:
                stds[c][f] = None
                continue
            stds[c][f] = statistics.pstdev(vals)
        vals = [v for v in stds[c].values() if v is not None]
        unit = "m" if c.endswith("_m") else "deg"
        thesis = (THESIS["appendix_a"]["position_std_m_max"] if unit == "m"
                  else THESIS["appendix_a"]["orientation_std_deg_max"])
        rows.append([c.replace("_m", "").replace("_deg", ""), unit, repr(max(vals)) if vals else "n/a",
                     repr(statistics.fmean(vals)) if vals else "n/a", str(sum(1 for v in vals if v != 0.0)),
                     str(len(vals)), f"up to {thesis}"])
    failed_frames = sorted({r["frame"] for run in frames for r in run if r["status"] != "ok"})
    failed_rows = sum(1 for run in frames for r in run if r["status"] != "ok")
    rep.h("Standard deviation of the estimate across runs")
    rep.p("Population standard deviation over the runs of each `est_*` column of `frames.csv` (6 decimals, so "
          "a difference below 5e-7 would not show here; the byte comparison below covers the rest). Frames per "
          "region: " + ", ".join(f"{g} {regions_count.get(g, 0)}" for g in REGIONS) +
          ". Frames the analyzer could not measure: "
          + (f"{len(failed_frames)} (frame {', '.join(map(str, failed_frames))}; {failed_rows} rows over all runs, "
             f"i.e. {'in every run' if failed_rows == len(failed_frames) * n_runs else 'NOT in every run'}); they "
             "have no estimate and are left out of the standard deviations." if failed_frames else "none."))
    rep.table(["Component", "Unit", "Max std over frames", "Mean std", "Frames with std > 0", "Frames",
               "Thesis (Appendix A)"], rows)

    rep.h("Byte identity of the outputs")
    rep.p("SHA-256 per run of: `frames.csv` without its six `ms_*` timing columns (the first 28 columns); "
          "`summary.json` without its `timing` object (parsed, `timing` removed, re-serialized with sorted keys, "
          "so equal hashes mean equal content); `calibration.yaml`; `run.json`; the reference PLY.")
    rows = []
    hashes = {k: [] for k in ("frames", "summary", "calibration", "run", "ply")}
    for d in run_dirs:
        h = {"frames": sha256_bytes(frames_csv_without_timing(d / "frames.csv")),
             "summary": sha256_bytes(summary_without_timing(d / "summary.json")),
             "calibration": sha256_file(d / "calibration.yaml"),
             "run": sha256_file(d / "run.json"),
             "ply": sha256_file(d / "reference_shelled.ply")}
        for k in hashes:
            hashes[k].append(h[k])
        rows.append([d.name] + [f"`{h[k][:16]}`" for k in ("frames", "summary", "calibration", "run", "ply")])
    rep.table(["Run", "frames.csv w/o ms_*", "summary.json w/o timing", "calibration.yaml", "run.json",
               "reference_shelled.ply"], rows, ["---"] * 6)
    verdict = {k: len(set(v)) == 1 for k, v in hashes.items()}
    rep.p("Identical across all runs: " + ", ".join(f"{k}: {'yes' if v else 'NO'}" for k, v in verdict.items())
          + ".")
    max_pos = max((v for c in COMPONENTS[:3] for v in stds[c].values() if v is not None), default=None)
    max_ori = max((v for c in COMPONENTS[3:] for v in stds[c].values() if v is not None), default=None)
    rep.p(f"Result: largest standard deviation {max_pos!r} m in position and {max_ori!r} deg in orientation "
          f"(thesis: up to {THESIS['appendix_a']['position_std_m_max']} m and "
          f"{THESIS['appendix_a']['orientation_std_deg_max']} deg). "
          + ("The analysis is deterministic: every run gives the same bytes."
             if all(verdict.values()) else "The runs differ; see the tables above."))

    rep.h("Figures")
    ranges = {f: rs[0]["range_m"] for f, rs in per_frame.items()}
    for kind, comps, unit, fig in (("position", COMPONENTS[:3], "m", 33), ("orientation", COMPONENTS[3:], "deg", 34)):
        path = ctx.out / f"determinism_{kind}_std.png"
        series = []
        for c in comps:
            fs = [f for f in sorted(stds[c]) if stds[c][f] is not None]
            series.append((c.split("_")[0], [ranges[f] for f in fs], [stds[c][f] for f in fs]))
        plots.scatter_vs_range(path, f"Standard deviation of {n_runs} estimations of {kind} "
                                     f"(cf. thesis Figure {fig})", f"standard deviation ({unit})", series,
                               guides="regions")
        rep.image(path, f"Standard deviation of {n_runs} estimations of {kind} per frame versus range "
                        f"(cf. thesis Figure {fig})")

    commands_section(ctx, rep)
    software_and_machine(ctx, rep, run_dirs[:1])
    path = finish(ctx, rep)
    if not all(verdict.values()):
        LOG("determinism: runs differ (reported, not an error)")
    return path


# ---------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------

EXPERIMENTS = {
    "characterization": (exp_characterization, "thesis Experiment 1: shelled vs full model at 558 positions "
                                                "(Tables 1-3, Figures 15-19)"),
    "conops": (exp_conops, "thesis Experiment 2: shelled vs full on the CONOPS path (Tables 4-5, Figures 20-24)"),
    "msaa": (exp_msaa, "thesis Experiment 3: MSAA x1-x32 calibration and the CONOPS path with/without MSAA "
                       "(Tables 6-11, Figures 25-32)"),
    "determinism": (exp_determinism, "thesis Appendix A: 10 analyses of the same frames, spread and byte identity"),
}


def parse_args(argv):
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--out", help="report folder (default reports/<experiment>; for `all`: reports/, one "
                                      "sub-folder per experiment)")
    common.add_argument("--datasets", default="datasets",
                        help="where datasets are rendered and reused (default: datasets/)")
    common.add_argument("--build", default="build", help="build folder with renderer/aar-render and "
                                                         "analyzer/aar-analyze (default: build/)")
    common.add_argument("--no-snapshot", action="store_true",
                        help="run the tools in --build itself instead of copies made at the start "
                             "(OUT/tools/), which keep a rebuild during the run out of the results")
    common.add_argument("--quick", action="store_true",
                        help="a few frames per region or range bin (smoke test, a few minutes for `all`)")
    parser = argparse.ArgumentParser(
        prog="aar_experiment.py",
        description="Reproduce Parsons (2017) chapter IV and Appendix A with aar-render and aar-analyze; "
                    "writes report.md, PNG plots and provenance per experiment.",
        epilog="Relative paths are taken from the current directory; commands run in the repository root. "
               "Exit status is non-zero when any step fails or an expected output is missing.")
    sub = parser.add_subparsers(dest="experiment", required=True, metavar="EXPERIMENT")
    for name, (_, text) in EXPERIMENTS.items():
        sub.add_parser(name, parents=[common], help=text, description=text)
    sub.add_parser("all", parents=[common], help="the four experiments in turn",
                   description="characterization, conops, msaa and determinism in turn")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv if argv is not None else sys.argv[1:])
    # Resolve user paths against the caller's directory before anything else.
    args.datasets = str(Path(args.datasets).resolve())
    args.build = str(Path(args.build).resolve())
    for tool in ("renderer/aar-render", "analyzer/aar-analyze"):
        if not os.access(Path(args.build) / tool, os.X_OK):
            print(f"aar_experiment: {Path(args.build) / tool} not found or not executable (build first: "
                  "bash scripts/build.sh)", file=sys.stderr)
            return 2
    names = list(EXPERIMENTS) if args.experiment == "all" else [args.experiment]
    if args.experiment == "all":
        out_root = Path(args.out).resolve() if args.out else ROOT / "reports"
        outs = {n: out_root / n for n in names}
    else:
        out_root = Path(args.out).resolve() if args.out else ROOT / "reports" / names[0]
        outs = {names[0]: out_root}
    Path(args.datasets).mkdir(parents=True, exist_ok=True)
    _analyzer_version()
    if not args.no_snapshot:
        # Run copies of the two executables, so that a rebuild of the build
        # folder during a long run cannot mix binaries within one report.
        snap = out_root / "tools"
        for tool in ("renderer/aar-render", "analyzer/aar-analyze"):
            (snap / tool).parent.mkdir(parents=True, exist_ok=True)
            tmp = snap / (tool + ".tmp")
            shutil.copy2(Path(args.build) / tool, tmp)
            os.replace(tmp, snap / tool)
            if subprocess.run([str(snap / tool), "--help"], capture_output=True).returncode != 0:
                print(f"aar_experiment: the copy of {Path(args.build) / tool} does not run "
                      "(was it being linked?); try again", file=sys.stderr)
                return 2
        LOG(f"tools: copied {rel(Path(args.build) / 'renderer/aar-render')} and "
            f"{rel(Path(args.build) / 'analyzer/aar-analyze')} to {rel(snap)} (--no-snapshot runs them in place)")
        args.tools_origin = rel(args.build)
        args.build = str(snap)
    memo = {}
    written = []
    timings = []
    t_all = time.monotonic()
    try:
        for name in names:
            outs[name].mkdir(parents=True, exist_ok=True)
            for old in outs[name].glob("*.png"):
                old.unlink()
            ctx = Ctx(name, args, outs[name], memo)
            LOG(f"{name}: start ({'quick' if args.quick else 'full'}; report in {rel(outs[name])}, "
                f"datasets in {rel(args.datasets)})")
            t = time.monotonic()
            written.append(EXPERIMENTS[name][0](ctx))
            timings.append((name, time.monotonic() - t))
            LOG(f"{name}: finished in {timings[-1][1]:.1f} s")
    except ExperimentError as e:
        LOG(f"FAILED: {e}")
        return 1
    total = time.monotonic() - t_all
    if args.experiment == "all":
        lines = ["# AAR experiments (Parsons 2017, chapter IV and Appendix A)", ""]
        if args.quick:
            lines += ["**QUICK MODE**: smoke-test frame selections, not a reproduction.", ""]
        lines += [f"Command: `experiments/aar_experiment.py all{' --quick' if args.quick else ''}`", "",
                  md_table(["Experiment", "Report", "Wall time (s; machine-dependent)"],
                           [[n, f"[{n}/report.md]({n}/report.md)", fmt(dt, 1)] for n, dt in timings]
                           + [["total", "", fmt(total, 1)]]), ""]
        index = out_root / "index.md"
        index.write_text("\n".join(lines))
        written.append(index)
    LOG(f"all done in {total:.1f} s")
    for path in written:
        print(rel(path))
    return 0


if __name__ == "__main__":
    sys.exit(main())
