#!/usr/bin/env python3
"""Side-by-side point-to-point ICP: aar-analyze against Open3D on identical clouds.

Runs `aar-analyze run` with the thesis's registration (point-to-point, model to
sensed, 30 iterations, 2 m gate) on the default preset's cleaned clouds and
dumps each frame's sensed cloud; then registers the same shelled model to the
same cloud from the same centroid seed with Open3D's
`registration_icp` (TransformationEstimationPointToPoint, 30 iterations, the
same gate), on one thread. Prints, per region, the median ICP time of both and
their ratio, and how far the two answers are apart.

A benchmark, not part of the tool: Open3D (Debian's python3-open3d) is needed
here only.

    /usr/bin/python3 experiments/bench_icp_open3d.py datasets/conops-x16 --frames 349:409 \
        --calibration results/conops-x16-calibration/calibration.yaml
"""
import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")  # one core, like aar-analyze
import numpy as np  # noqa: E402

try:
    import open3d as o3d  # noqa: E402
except ImportError:
    sys.exit("bench_icp_open3d: needs Open3D (apt-get install python3-open3d)")

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
import aar_stereo  # noqa: E402


def rigid_fit(source, target):
    """target = R source + t (Kabsch), for recovering aar-analyze's estimate."""
    cs, ct = source.mean(axis=0), target.mean(axis=0)
    u, _, vt = np.linalg.svd((source - cs).T @ (target - ct))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    return r, ct - r @ cs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--frames", default="349:409", help="half-open range a:b (default: 60 region C frames)")
    parser.add_argument("--calibration", required=True)
    parser.add_argument("--analyzer", default="build/analyzer/aar-analyze")
    args = parser.parse_args()
    first, last = (int(v) for v in args.frames.split(":"))

    with tempfile.TemporaryDirectory(prefix="aar-o3d-") as tmp:
        shell = pathlib.Path(tmp) / "shell.ply"
        subprocess.run([args.analyzer, "reference", "--model", "shelled", "--out", str(shell)], check=True,
                       stdout=subprocess.DEVNULL)
        out = pathlib.Path(tmp) / "run"
        subprocess.run([args.analyzer, "run", args.dataset, "--frames", args.frames, "--calibration",
                        args.calibration, "--registration", "point_to_point", "--correspondence", "model_to_sensed",
                        "--icp-iterations", "30", "--max-correspondence", "2", "--no-progress", "--out", str(out),
                        "--dump-frames", ",".join(str(i) for i in range(first, last))], check=True,
                       stdout=subprocess.DEVNULL)
        model = aar_stereo.read_ply(shell)
        model_cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(model))
        run = aar_stereo.open_run(out)
        by_region = {}
        for r in (r for r in run if r["status"] == "ok"):
            dump = run.dumps[r["frame"]]
            sensed = dump.sensed()
            ours_r, ours_t = rigid_fit(model, dump.model())
            init = np.eye(4)
            init[:3, 3] = sensed.mean(axis=0) - model.mean(axis=0)  # aar-analyze's centroid seed
            target = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(sensed))
            criteria = o3d.pipelines.registration.ICPConvergenceCriteria(relative_fitness=0.0, relative_rmse=0.0,
                                                                         max_iteration=30)
            start = time.perf_counter()
            result = o3d.pipelines.registration.registration_icp(
                model_cloud, target, 2.0, init, o3d.pipelines.registration.TransformationEstimationPointToPoint(),
                criteria)
            o3d_ms = 1000.0 * (time.perf_counter() - start)
            t = np.asarray(result.transformation)
            dr = t[:3, :3] @ ours_r.T
            angle = np.degrees(np.arccos(np.clip((np.trace(dr) - 1.0) / 2.0, -1.0, 1.0)))
            by_region.setdefault(r["region"], []).append(
                (r["ms_icp"], o3d_ms, np.linalg.norm(t[:3, 3] - ours_t), angle, len(sensed)))

    print(f"point-to-point ICP, model to sensed, 30 iterations, 2 m gate, one thread; frames {args.frames}")
    print("| region | frames | sensed points (median) | aar-analyze ms (median) | Open3D ms (median) | "
          "Open3D / aar-analyze | position apart (median, m) | attitude apart (median, deg) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for region in sorted(by_region):
        a = np.array(by_region[region])
        med = np.median(a, axis=0)
        ratio = np.median(a[:, 1] / a[:, 0])
        print(f"| {region} | {len(a)} | {med[4]:.0f} | {med[0]:.2f} | {med[1]:.2f} | {ratio:.2f} | "
              f"{med[2]:.4f} | {med[3]:.4f} |")


if __name__ == "__main__":
    main()
