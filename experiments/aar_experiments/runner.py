"""Running the tools: one experiment's context, aar-render and aar-analyze calls, provenance.

Every call is logged on stderr and recorded in the experiment's command list
(reported under "Commands run"); analyses with the same inputs within one
invocation are done once and reused.
"""

import hashlib
import os
import platform
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

from .outputs import read_json

ROOT = Path(__file__).resolve().parents[2]

# Frame selections. None = every frame of the flight path. ("shard", "K/N")
# = frames i with i % N == K, spread over the whole path.
# ("frames", "a:b") = the frames a to b - 1; ("frames", "a:b", "K/N") = those
# of them with i % N == K.
SELECTIONS = {
    # realism 0/6: 102 frames, 20 in A, 39 in B, 43 in C.
    "full": {"char": None, "conops": None, "conops_thesis": None, "determinism": ("shard", "0/15"),
             "determinism_runs": 10, "realism": ("shard", "0/6")},
    # char 0/56: 10 frames, 4 in 20-60 m, 5 in 60-110 m; conops 0/61: 10
    # frames, 2 in A, 4 in B, 4 in C; conops_thesis (the thesis geometry,
    # conops.py): 28 frames at 40.5-35.4 m, the 14 with the tail out of view
    # (343-356) and 7 on either side.
    # realism: frames 391, 456, 521 and 586, region C (32-38 m).
    "quick": {"char": ("shard", "0/56"), "conops": ("shard", "0/61"), "conops_thesis": ("frames", "336:364"),
              "determinism": ("shard", "0/61"), "determinism_runs": 10, "realism": ("frames", "349:609", "1/65")},
}


class ExperimentError(Exception):
    pass


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


def selection_args(selection):
    if selection is None:
        return []
    kind, value = selection[:2]
    return ["--" + kind, value] + (["--shard", selection[2]] if len(selection) > 2 else [])


def selection_text(selection):
    if selection is None:
        return "all frames"
    kind, value = selection[:2]
    if kind == "frames":
        a, b = value.split(":")
        if len(selection) > 2:
            k, n = selection[2].split("/")
            return (f"frames i from {a} to {int(b) - 1} with i % {n} == {k} "
                    f"(--frames {value} --shard {selection[2]})")
        return f"frames {a} to {int(b) - 1} (--frames {value})"
    return f"frames i with i % {value.split('/')[1]} == {value.split('/')[0]} (--shard {value})"


def selected_frames(selection, count):
    """The frame indices a selection picks from a flight path of `count` samples, ascending."""
    if selection is None:
        return list(range(count))
    kind, value = selection[:2]
    if kind == "frames":
        a, b = (int(v) for v in value.split(":"))
        frames = list(range(max(a, 0), min(b, count)))
        if len(selection) > 2:
            k, n = (int(v) for v in selection[2].split("/"))
            frames = [i for i in frames if i % n == k]
        return frames
    k, n = (int(v) for v in value.split("/"))
    return list(range(k, count, n))


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
        self.background = getattr(args, "background", "flat")
        self.geometry = getattr(args, "geometry", None) or "default"
        self.sel = SELECTIONS["quick" if args.quick else "full"]
        if getattr(args, "shard", None):
            self.sel = dict(self.sel, conops=("shard", args.shard), conops_thesis=("shard", args.shard),
                            realism=("shard", args.shard))
        self.memo = memo            # shared across experiments of one `all`
        self.commands = []          # (step, command line, seconds or None when reused)
        self.datasets_used = {}     # name -> path
        self.pngs = []
        self.binaries = {}          # tool name -> SHA-256 of the binary at each call
        self.tools_origin = getattr(args, "tools_origin", None)
        self.render = self.build / "renderer" / "aar-render"
        self.analyze = self.build / "analyzer" / "aar-analyze"
        self.make_flightpaths = self.build / "flightpaths" / "aar-make-flightpaths"

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


THESIS_BOARDS = ("--far-boards", "none")


def render_calib(ctx, dataset, msaa, rig=None, boards=THESIS_BOARDS):
    """Calibration board pairs: by default the thesis's 12 (`--far-boards none`: aar-render's default adds the
    twelve again at 30 and 45 m; the thesis's experiments keep the thesis's set so that their tables stay
    comparable with it), else the `aar-render calib` flags `boards`; `rig` (a rig JSON) other than aar-render's
    default scenes/rig.json must be the one the dataset's frames are rendered with."""
    _render(ctx, f"render calibration boards into {dataset.name} (x{msaa}{', ' + ' '.join(boards) if boards else ''})",
            [ctx.render, "calib", dataset, "--msaa", msaa, *boards] + (["--rig", rig] if rig else []), dataset)


def render_frames(ctx, dataset, msaa, flight_path, selection, extra=()):
    argv = [ctx.render, "render", dataset, "--msaa", msaa, "--flight-path", flight_path, *extra]
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


# The pipeline docs/results.md was measured with: the thesis preset with the
# loose shell, sensed-to-model pairing and 1/32 px disparity offset
# (`aar-analyze run --help`; docs/analysis.md, "Presets").
PUBLISHED_PIPELINE = ("--preset", "thesis", "--shell", "loose", "--disparity-offset", "0.03125")
PUBLISHED_PAIRING = ("--correspondence", "sensed_to_model")


def analyze(ctx, run_name, dataset, model, selection, calibration=None, reuse=True, label="", extra=()):
    """aar-analyze run; the same inputs within one invocation reuse the earlier run."""
    key = ("run", str(dataset), model, repr(selection), str(calibration), tuple(extra))
    if reuse and key in ctx.memo:
        ctx.commands.append((f"analyze {dataset.name} with the {model} model (reused: {rel(ctx.memo[key])})", "", None))
        return Path(ctx.memo[key])
    out = ctx.out / "runs" / run_name
    if out.exists():
        shutil.rmtree(out)
    argv = [ctx.analyze, "run", dataset, "--model", model]
    if "--preset" not in extra:  # an explicit preset runs as it is
        argv += ["--icp-iterations", "30", *PUBLISHED_PIPELINE]
        if "--correspondence" not in extra:
            argv += list(PUBLISHED_PAIRING)
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
# Provenance: datasets, binaries, versions, the machine
# ---------------------------------------------------------------------------

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


def binary_hashes(ctx, tool):
    hashes = sorted(ctx.binaries.get(Path(tool).name, set()))
    if not hashes:
        return f"`{sha256_file(tool)}` (not called in this experiment)"
    text = ", ".join(f"`{h}`" for h in hashes)
    if len(hashes) > 1:
        text += " (**the binary changed during the experiment**: it was rebuilt meanwhile)"
    return text


_ANALYZER_VERSION = None


def analyzer_version():
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


def dpkg_version(package):
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", package],
                             capture_output=True, text=True)
        return out.stdout.strip() or None
    except OSError:
        return None


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"
