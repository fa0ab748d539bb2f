#!/usr/bin/env python3
"""Kills `aar-render render` (a resume), `aar-analyze calibrate` and
`aar-analyze export` with SIGKILL at random moments and checks what is left.

- calibrate and export write their output folder as a unit: after every kill
  the folder is, byte for byte, either the previous output or the new one.
- a render resume adds frames one file at a time: after every kill each file
  is byte for byte the old dataset's or the finished dataset's (no partial
  file under a final name), and a rerun finishes the dataset byte for byte.
After the kills, the next command clears what the killed ones left.

Usage: kill_test.py --build BUILD [--kills 20] [--seed 1] [--work DIR]
"""

import argparse
import hashlib
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Lock files are not content: flock needs them, and they stay empty.
LOCKS = {".aar-manifest.lock", ".aar-writers.lock"}


def snapshot(folder):
    """relative path -> SHA-256 of every file under `folder` (lock files and .tmp* leftovers apart)."""
    files = {}
    for path in sorted(Path(folder).rglob("*")):
        if path.is_file() and path.name not in LOCKS and not path.name.startswith(".tmp"):
            files[str(path.relative_to(folder))] = hashlib.sha256(path.read_bytes()).hexdigest()
    return files


def run(argv, check=True):
    result = subprocess.run([str(a) for a in argv], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env={k: v for k, v in os.environ.items() if not k.startswith("SLURM_")})
    if check and result.returncode != 0:
        sys.exit(f"kill_test: {' '.join(map(str, argv))} failed ({result.returncode}):\n{result.stdout}")
    return result


def timed(argv):
    start = time.monotonic()
    run(argv)
    return time.monotonic() - start


def kill_at(argv, seconds):
    """Starts `argv`, sends SIGKILL after `seconds` (unless it ended), returns its exit code."""
    process = subprocess.Popen([str(a) for a in argv], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               env={k: v for k, v in os.environ.items() if not k.startswith("SLURM_")})
    try:
        return process.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGKILL)
        return process.wait()


def copy_tree(source, target):
    if target.exists():
        shutil.rmtree(target)
    shutil.copytree(source, target, symlinks=True)


def check_whole(name, argv, out, old, new, kills, rng, duration):
    """Kills `argv` (which writes `out` from `old` to `new`) `kills` times; `out` must be old or new each time."""
    finished = 0
    for k in range(kills):
        state = snapshot(out)
        if state != old:  # back to the old output for the next try
            shutil.rmtree(out)
            copy_tree(out.parent / (out.name + "-old"), out)
        code = kill_at(argv, rng.uniform(0.0, duration))
        state = snapshot(out)
        finished += code == 0
        if state not in (old, new):
            changed = sorted(set(state.items()) ^ set(old.items()))[:4]
            sys.exit(f"kill_test: {name}, kill {k}: {out} is neither the old nor the new output: {changed}")
    result = run(argv)
    if snapshot(out) != new:
        sys.exit(f"kill_test: {name}: the run after the kills did not write the new output")
    leftovers = [p.name for p in out.parent.iterdir() if p.name.startswith("." + out.name + ".aar-staging")]
    if leftovers:
        sys.exit(f"kill_test: {name}: {leftovers} left beside {out}")
    print(f"{name}: {kills} kills ({kills - finished} during the run): the folder was always the old or the new "
          f"output; the next run cleaned up ({result.returncode})")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", required=True, type=Path, help="build folder with renderer/ and analyzer/")
    parser.add_argument("--kills", type=int, default=20, help="kills per command (20)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the kill times (1)")
    parser.add_argument("--work", type=Path, help="scratch folder (default BUILD/test-tmp/kill)")
    args = parser.parse_args()
    render = args.build.resolve() / "renderer" / "aar-render"
    analyze = args.build.resolve() / "analyzer" / "aar-analyze"
    work = (args.work or args.build / "test-tmp" / "kill").resolve()
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    rng = random.Random(args.seed)

    # The dataset: every board pair and six frames with depth, x1.
    dataset = work / "dataset"
    run([render, "calib", dataset, "--msaa", "1", "--no-progress"])
    render_frames = [render, "render", dataset, "--msaa", "1", "--depth", "--no-progress",
                     "--flight-path", ROOT / "flightpaths/conops.csv"]
    run(render_frames + ["--frames", "590:593"])
    old_dataset = work / "dataset-old"
    copy_tree(dataset, old_dataset)
    duration = timed(render_frames + ["--frames", "590:596"])
    new_dataset = snapshot(dataset)

    # Render: resumed from three frames to six, killed; every file old or new, then finished by a rerun.
    old = snapshot(old_dataset)
    for k in range(args.kills):
        copy_tree(old_dataset, dataset)
        kill_at(render_frames + ["--frames", "590:596"], rng.uniform(0.0, duration))
        for path, digest in snapshot(dataset).items():
            if digest not in (old.get(path), new_dataset.get(path)):
                sys.exit(f"kill_test: render resume, kill {k}: {path} is neither the old nor the finished file")
    run(render_frames + ["--frames", "590:596"])
    if snapshot(dataset) != new_dataset:
        sys.exit("kill_test: render resume: the rerun after the kills did not finish the dataset byte for byte")
    leftovers = [str(p) for p in dataset.rglob(".tmp*")]
    if leftovers:
        sys.exit(f"kill_test: render resume: {leftovers} left after the rerun")
    print(f"render resume: {args.kills} kills: every file was the old or the finished one; the rerun finished the "
          "dataset byte for byte")

    # Calibrate: pinhole before, the rig's lens model (auto) after.
    out = work / "calibration"
    run([analyze, "calibrate", dataset, "--distortion", "brown-conrady", "--out", out])
    copy_tree(out, work / "calibration-old")
    old = snapshot(out)
    calibrate = [analyze, "calibrate", dataset, "--distortion", "pinhole", "--out", out]
    duration = timed(calibrate)
    new = snapshot(out)
    copy_tree(work / "calibration-old", out)
    check_whole("calibrate", calibrate, out, old, new, args.kills, rng, duration)

    # Export: six frames before, three after (no stale images may stay).
    out = work / "bop"
    run([analyze, "export", dataset, "--format", "bop", "--frames", "590:596", "--out", out])
    copy_tree(out, work / "bop-old")
    old = snapshot(out)
    export = [analyze, "export", dataset, "--format", "bop", "--frames", "590:593", "--out", out]
    duration = timed(export)
    new = snapshot(out)
    copy_tree(work / "bop-old", out)
    check_whole("export", export, out, old, new, args.kills, rng, duration)
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
