"""The command line: one subcommand per registered experiment, and `all`."""

import argparse
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from .registry import experiments
from .report import fmt, md_table
from .runner import LOG, ROOT, Ctx, ExperimentError, analyzer_version, rel

_COUNTS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten")


def _in_turn(names):
    """"a, b and c" for `all`'s description."""
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def parse_args(argv, registered):
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
    common.add_argument("--background", default="flat", choices=("flat", "sky", "terrain", "clouds"),
                        help="conops only: what is behind the receiver (aar-render render --background); other "
                             "than flat, the path is rendered with depth truth into conops-x16-BACKGROUND and the "
                             "report adds the sensed cloud against the truth (default: flat, the thesis's sky)")
    common.add_argument("--geometry", choices=("default", "thesis"),
                        help="conops only: the rig and flight path. default: scenes/rig.json with "
                             "flightpaths/conops.csv (the receiver always in view); thesis: scenes/rig-thesis.json "
                             "with flightpaths/conops-level.csv (the T-tail out of view at 39.2-36.6 m), into "
                             "conops-thesis-x16, report in reports/conops-thesis unless --out, with the same frames "
                             "of the default geometry as a control. `conops` alone: default; `all`: both, the thesis "
                             "geometry's report in OUT/conops-thesis (`all --quick`: default only), unless one is "
                             "named")
    common.add_argument("--shard", metavar="K/N",
                        help="conops and realism only: render and analyze the frames i with i %% N == K (a subset "
                             "spread over the whole path) instead of every frame (conops) or every 6th (realism)")
    common.add_argument("--quick", action="store_true",
                        help="a few frames per region or range bin (smoke test, a few minutes for `all`)")
    parser = argparse.ArgumentParser(
        prog="aar_experiment.py",
        description="Reproduce Parsons (2017) chapter IV and Appendix A with aar-render and aar-analyze, and "
                    "measure what the thesis's world lacked (realism); writes report.md, PNG plots and "
                    "provenance per experiment.",
        epilog="Relative paths are taken from the current directory; commands run in the repository root. "
               "Exit status is non-zero when any step fails or an expected output is missing.")
    sub = parser.add_subparsers(dest="experiment", required=True, metavar="EXPERIMENT")
    for name, experiment in registered.items():
        sub.add_parser(name, parents=[common], help=experiment.help, description=experiment.help)
    count = _COUNTS[len(registered)] if len(registered) < len(_COUNTS) else str(len(registered))
    sub.add_parser("all", parents=[common], help=f"the {count} experiments in turn (conops on both geometries)",
                   description=f"{_in_turn(list(registered))} in turn; conops on both geometries (--geometry; "
                               "with --quick on the default one unless --geometry thesis)")
    return parser.parse_args(argv)


def _snapshot_tools(args, out_root):
    """Copies the executables (aar-render, aar-analyze, aar-make-flightpaths) into OUT/tools/, so that a rebuild
    of the build folder during a long run cannot mix binaries within one report; returns False when a copy does
    not run."""
    snap = out_root / "tools"
    for tool in ("renderer/aar-render", "analyzer/aar-analyze", "flightpaths/aar-make-flightpaths"):
        (snap / tool).parent.mkdir(parents=True, exist_ok=True)
        tmp = snap / (tool + ".tmp")
        shutil.copy2(Path(args.build) / tool, tmp)
        os.replace(tmp, snap / tool)
        if subprocess.run([str(snap / tool), "--help"], capture_output=True).returncode != 0:
            print(f"aar_experiment: the copy of {Path(args.build) / tool} does not run "
                  "(was it being linked?); try again", file=sys.stderr)
            return False
    LOG(f"tools: copied aar-render, aar-analyze and aar-make-flightpaths from {rel(args.build)} to {rel(snap)} "
        "(--no-snapshot runs them in place)")
    args.tools_origin = rel(args.build)
    args.build = str(snap)
    return True


def _write_index(args, out_root, timings, total):
    lines = ["# AAR experiments (Parsons 2017, chapter IV and Appendix A)", ""]
    if args.quick:
        lines += ["**QUICK MODE**: smoke-test frame selections, not a reproduction.", ""]
    lines += [f"Command: `experiments/aar_experiment.py all{' --quick' if args.quick else ''}`", "",
              md_table(["Experiment", "Report", "Wall time (s; machine-dependent)"],
                       [[n, f"[{n}/report.md]({n}/report.md)", fmt(dt, 1)] for n, dt in timings]
                       + [["total", "", fmt(total, 1)]]), ""]
    index = out_root / "index.md"
    index.write_text("\n".join(lines))
    return index


def main(argv=None):
    registered = experiments()
    args = parse_args(argv if argv is not None else sys.argv[1:], registered)
    # Resolve user paths against the caller's directory before anything else.
    args.datasets = str(Path(args.datasets).resolve())
    args.build = str(Path(args.build).resolve())
    for tool in ("renderer/aar-render", "analyzer/aar-analyze"):
        if not os.access(Path(args.build) / tool, os.X_OK):
            print(f"aar_experiment: {Path(args.build) / tool} not found or not executable (build first: "
                  "bash scripts/build.sh)", file=sys.stderr)
            return 2
    # Jobs: (report name, experiment, geometry). `all` runs Experiment 2 on both geometries (`all --quick` on
    # the default one only: the thesis geometry's quick run, 28 frames on each geometry and nine analyses,
    # tripled the quick conops time) unless --geometry names one.
    if args.experiment == "all":
        jobs = []
        for n in registered:
            if n != "conops":
                jobs.append((n, n, None))
                continue
            both = ["default"] if args.quick else ["default", "thesis"]
            for geometry in ([args.geometry] if args.geometry else both):
                jobs.append(("conops-thesis" if geometry == "thesis" else n, n, geometry))
        out_root = Path(args.out).resolve() if args.out else ROOT / "reports"
        outs = {j[0]: out_root / j[0] for j in jobs}
    else:
        geometry = args.geometry if args.experiment == "conops" else None
        job = ("conops-thesis" if geometry == "thesis" else args.experiment, args.experiment, geometry)
        jobs = [job]
        out_root = Path(args.out).resolve() if args.out else ROOT / "reports" / job[0]
        outs = {job[0]: out_root}
    Path(args.datasets).mkdir(parents=True, exist_ok=True)
    analyzer_version()
    if not args.no_snapshot and not _snapshot_tools(args, out_root):
        return 2
    memo = {}
    written = []
    timings = []
    t_all = time.monotonic()
    try:
        for name, experiment, geometry in jobs:
            outs[name].mkdir(parents=True, exist_ok=True)
            for old in outs[name].glob("*.png"):
                old.unlink()
            ctx = Ctx(name, argparse.Namespace(**dict(vars(args), geometry=geometry)), outs[name], memo)
            LOG(f"{name}: start ({'quick' if args.quick else 'full'}; report in {rel(outs[name])}, "
                f"datasets in {rel(args.datasets)})")
            t = time.monotonic()
            written.append(registered[experiment].run(ctx))
            timings.append((name, time.monotonic() - t))
            LOG(f"{name}: finished in {timings[-1][1]:.1f} s")
    except ExperimentError as e:
        LOG(f"FAILED: {e}")
        return 1
    total = time.monotonic() - t_all
    if args.experiment == "all":
        written.append(_write_index(args, out_root, timings, total))
    LOG(f"all done in {total:.1f} s")
    for path in written:
        print(rel(path))
    return 0
