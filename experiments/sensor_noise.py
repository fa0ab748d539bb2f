#!/usr/bin/python3
"""Calibration and pose error against sensor noise (issue 9, item 4).

    experiments/sensor_noise.py --levels none,4000,1000,250 --msaa 4 --shard 0/10 --work results/sensor-noise \
        [--pairing symmetric]

For each level, the exposure in electrons at radiance 1.0 (`none`: no sensor
block, the noise-free renderer), writes a rig: scenes/rig.json with a sensor
block whose `exposure_e` is the level and whose other fields are the
defaults of common/include/aar/sensor.h, without blur or mosaic, so that only
the noise changes. Then, into WORK/<level>/: renders the CONOPS path
(`--shard`) and the twelve calibration pairs at `--msaa`, calibrates from
them (`aar-analyze calibrate`), analyzes with the default preset and that
calibration (`aar-analyze run`), and reads the results back. Steps whose
output exists are skipped (the renders resume by themselves).

Writes WORK/table.md (WORK/table-PAIRING.md with --pairing; per level: the sky's noise in 8-bit codes, measured on
the left image of the first frame; the calibration's RMS re-projection
error, focal and baseline error against the rig; per region the mean
absolute error of each degree of freedom) and WORK/sensor_noise.png.
docs/rendering.md, "Sensor model", shows the table and the commands.
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "experiments"))
from aar_experiments.outputs import calibration_errors, read_summary  # noqa: E402  (shared with the realism experiment)
from aar_experiments.thesis import COMPONENTS, REGIONS  # noqa: E402


def run(command):
    print("+", " ".join(str(c) for c in command), flush=True)
    subprocess.run([str(c) for c in command], check=True)


def write_rig(level, path):
    rig = json.loads((REPO / "scenes/rig.json").read_text())
    if level != "none":
        rig["schema"] = "aar-rig/3"
        rig["sensor"] = {"exposure_e": float(level)}
    rig["description"] = f"scenes/rig.json with sensor exposure {level} (experiments/sensor_noise.py)"
    path.write_text(json.dumps(rig, indent=2) + "\n")


def measure(level, args):
    work = Path(args.work) / level
    run_name = f"run-{args.pairing}" if args.pairing else "run"
    dataset, calib_out, run_out = work / "dataset", work / "calibration", work / run_name
    work.mkdir(parents=True, exist_ok=True)
    rig = work / "rig.json"
    write_rig(level, rig)
    render = [args.render, "render", dataset, "--rig", rig, "--msaa", args.msaa, "--shard", args.shard,
              "--no-progress"]
    run(render)
    run([args.render, "calib", dataset, "--rig", rig, "--msaa", args.msaa, "--far-boards", "none", "--no-progress"])
    if not (calib_out / "calibration_report.json").exists():
        run([args.analyze, "calibrate", dataset, "--out", calib_out])
    if not (run_out / "summary.json").exists():
        pairing = ["--pairing", args.pairing] if args.pairing else []
        run([args.analyze, "run", dataset, "--shard", args.shard, "--calibration", calib_out / "calibration.yaml",
             "--out", run_out, "--no-progress"] + pairing)
    calibration = calibration_errors(calib_out)
    summary = read_summary(run_out)["models"]["shelled"]
    first = min(dataset.glob("frames/*_left.png"))
    sky = matplotlib.image.imread(first)[:64, :64, :3] * 255.0  # the top-left corner: sky in every frame
    return {
        "level": level,
        "sky_noise_codes": float(np.mean(np.std(sky, axis=(0, 1), ddof=1))),
        "rms_px": calibration["rms_px"],
        "focal_error_percent": calibration["focal_error_percent"],
        "baseline_error_percent": calibration["baseline_error_percent"],
        "regions": {r: {"ok": summary[r]["ok"], "frames": summary[r]["frames"],
                        "mae": summary[r]["mean_abs_error"]} for r in REGIONS if r in summary},
    }


def table(rows):
    lines = ["| Exposure (e- at 1.0) | Sky noise (codes) | Calib. RMS (px) | Focal err. (%) | Baseline err. (%) | Region"
             " | Frames (ok/all) | " + " | ".join(f"MAE {c}" for c in COMPONENTS) + " |",
             "|---|---:|---:|---:|---:|---|---:|" + "---:|" * len(COMPONENTS)]
    for row in rows:
        for region, r in row["regions"].items():
            lines.append(f"| {row['level']} | {row['sky_noise_codes']:.2f} | {row['rms_px']:.4f} | "
                         f"{row['focal_error_percent']:.3f} | {row['baseline_error_percent']:.3f} | {region} | "
                         f"{r['ok']}/{r['frames']} | " + " | ".join(f"{r['mae'][c]:.3f}" for c in COMPONENTS) + " |")
    return "\n".join(lines) + "\n"


def plot(rows, path):
    x = [row["sky_noise_codes"] for row in rows]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].plot(x, [row["rms_px"] for row in rows], "o-")
    axes[0].set_ylabel("calibration RMS re-projection error (px)")
    for region, marker in zip(REGIONS, "os^"):
        present = [row for row in rows if region in row["regions"]]
        xs = [row["sky_noise_codes"] for row in present]
        axes[1].plot(xs, [row["regions"][region]["mae"]["x_m"] for row in present], marker + "-", label=region)
        axes[2].plot(xs, [row["regions"][region]["mae"]["pitch_deg"] for row in present], marker + "-",
                     label=region)
    axes[1].set_ylabel("mean absolute error x (m)")
    axes[2].set_ylabel("mean absolute error pitch (deg)")
    for ax in axes:
        ax.set_xlabel("sky noise, standard deviation (8-bit codes)")
        ax.grid(alpha=0.3)
    for ax in axes[1:]:
        ax.set_yscale("log")
        ax.legend(title="region")
    for row, xi in zip(rows, x):
        axes[0].annotate(row["level"], (xi, row["rms_px"]), textcoords="offset points", xytext=(4, 4), fontsize=8)
    fig.suptitle("Sensor noise against calibration and pose error (exposure in e- at radiance 1.0 annotated)")
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="none,4000,1000,250",
                        help="exposures [e- at radiance 1.0], comma-separated; none = no sensor")
    parser.add_argument("--msaa", default="4")
    parser.add_argument("--shard", default="0/10", help="frames i with i %% N == K of flightpaths/conops.csv")
    parser.add_argument("--work", default="results/sensor-noise")
    parser.add_argument("--render", default=str(REPO / "build/renderer/aar-render"))
    parser.add_argument("--analyze", default=str(REPO / "build/analyzer/aar-analyze"))
    parser.add_argument("--pairing", default="",
                        help="aar-analyze run --pairing (default: the analyzer's); results in WORK/<level>/run-PAIRING")
    args = parser.parse_args(argv)
    rows = [measure(level, args) for level in args.levels.split(",")]
    work = Path(args.work)
    stem = f"-{args.pairing}" if args.pairing else ""
    outputs = [work / f"table{stem}.md", work / f"results{stem}.json", work / f"sensor_noise{stem}.png"]
    outputs[0].write_text(table(rows))
    outputs[1].write_text(json.dumps(rows, indent=1) + "\n")
    plot(rows, outputs[2])
    print(table(rows))
    print("wrote " + ", ".join(str(o) for o in outputs))


if __name__ == "__main__":
    main(sys.argv[1:])
