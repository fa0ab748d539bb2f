"""Reading the tools' outputs: frames.csv, summary.json, run.json, frame sidecars.

Plain values out (dicts, tuples in thesis.COMPONENTS order), so the
experiments and plots know the file formats only through this module, which
reads run folders and datasets with the repository's python/aar_stereo.
"""

import json
import sys
from pathlib import Path

from .thesis import COMPONENTS

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
import aar_stereo  # noqa: E402


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_frames(run_dir):
    """frames.csv of a run folder: one dict per row, typed (aar_stereo.read_frames_csv)."""
    return aar_stereo.open_run(run_dir).frames


def read_summary(run_dir):
    return aar_stereo.open_run(run_dir).summary


def read_run_json(run_dir):
    return aar_stereo.open_run(run_dir).record


def ok_rows(rows):
    return [r for r in rows if r["status"] == "ok"]


def pairing_of(run_dir):
    """ICP pairing direction a run used, from its run.json."""
    return read_run_json(run_dir).get("options", {}).get("icp", {}).get("correspondence", "?")


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


def group_table(key_model, groups, kind):
    """{group: {label: tuple}} from {label: (summary, model)}: one statistic of several runs per group."""
    return {g: {label: group_stats(s, m, g, kind) for label, (s, m) in key_model.items()} for g in groups}


def group_table_counts(key_model, groups):
    """{group: {label: (ok, all) frames}} from {label: (summary, model)}."""
    return {g: {label: group_counts(s, m, g) for label, (s, m) in key_model.items()} for g in groups}


def sidecar(dataset, frame):
    """The truth sidecar of a frame of a dataset, checked against the dataset's manifest."""
    return aar_stereo.open_dataset(dataset, verify=False).frame(frame).sidecar


def summary_without_timing(path):
    s = read_json(path)
    s.pop("timing", None)
    return json.dumps(s, sort_keys=True, indent=1).encode()


def frames_csv_without_timing(path):
    """frames.csv without its ms_* timing columns (named in the header), as bytes."""
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    keep = [i for i, name in enumerate(lines[0].split(",")) if not name.startswith("ms_")]
    return "".join(",".join(line.split(",")[i] for i in keep) + "\n" for line in lines).encode()


# Errors of a calibration against the rig it was rendered with (calibration_report.json; docs/analysis.md,
# "Calibration"): key, heading, digits. The ray error is the larger of the two cameras' largest distance,
# over the image, between a pixel undistorted with the estimate and with the rig's own lens.
CALIBRATION_ERRORS = (("rms_px", "RMS re-projection (px)", 4), ("epipolar_px", "Epipolar (px)", 4),
                      ("focal_error_percent", "Focal error (%)", 3),
                      ("baseline_error_percent", "Baseline error (%)", 3),
                      ("principal_point_error_px", "Left principal point error (px)", 3),
                      ("rotation_error_deg", "Rotation error (deg)", 4),
                      ("ray_error_max_px", "Largest ray error (px)", 3))


def calibration_errors(calibration_dir):
    """{key of CALIBRATION_ERRORS: value (None when absent), "pairs": pairs used, "distortion": whether the
    lens was estimated} from calibration_dir/calibration_report.json."""
    r = read_json(calibration_dir / "calibration_report.json")
    v = r.get("versus_ideal", {})
    rays = [v[k] for k in ("left_ray_error_max_px", "right_ray_error_max_px") if v.get(k) is not None]
    return {"rms_px": r["rms_reprojection_px"], "epipolar_px": r.get("epipolar_error_px"),
            "focal_error_percent": v.get("focal_error_percent"),
            "baseline_error_percent": v.get("baseline_error_percent"),
            "principal_point_error_px": v.get("left_principal_point_error_px"),
            "rotation_error_deg": v.get("rotation_error_deg"), "ray_error_max_px": max(rays) if rays else None,
            "pairs": r.get("used_pairs"), "distortion": "distortion" in r}
