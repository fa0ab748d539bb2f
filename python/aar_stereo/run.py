"""Output folders of `aar-analyze run` (and `merge`; docs/analysis.md, "Output folder of `run`")."""

import re
from functools import cached_property
from pathlib import Path

import numpy as np

from .calibration import read_calibration
from .errors import DataError
from .formats import FrameSequence, parse_float, read_csv, read_json, read_ply, read_png, require_file

# frames.csv's column types; every other column is a float (None where empty).
INT_COLUMNS = frozenset({"frame", "sensed_points", "icp_iterations", "icp_inliers", "truth_points",
                         "truth_off_receiver", "truth_off_surface", "truth_on_propellers", "truth_propellers_kept"})
BOOL_COLUMNS = frozenset({"icp_converged"})
TEXT_COLUMNS = frozenset({"region", "status"})
FRACTION_COLUMN = "truth_error_by_fraction"  # "count/sum" pairs, space-separated
VSD_COLUMN = "vsd_errors"  # e_VSD at the 10 tolerances, space-separated
VSD_TAUS = 10
REQUIRED = ("run.json", "frames.csv", "summary.json")
DUMP = re.compile(r"(\d{6})_(disparity\.png|sensed\.ply|model\.ply|overlay\.png|points\.csv)")


def _int(text, path, line, column):
    try:
        return int(text)
    except ValueError:
        raise DataError(path, f"{column}: '{text}' is not an integer", line) from None


def _value(column, text, path, line):
    if column in TEXT_COLUMNS:
        return text
    if column in INT_COLUMNS:
        return _int(text, path, line, column)
    if column in BOOL_COLUMNS:
        if text not in ("0", "1"):
            raise DataError(path, f"{column}: '{text}' is not 0 or 1", line)
        return text == "1"
    if column == FRACTION_COLUMN:
        pairs = [item.partition("/") for item in text.split()]
        return tuple((_int(n, path, line, column), parse_float(s, path, line, column)) for n, _, s in pairs)
    if column == VSD_COLUMN:
        if not text:
            return None
        errors = tuple(parse_float(item, path, line, column) for item in text.split())
        if len(errors) != VSD_TAUS:
            raise DataError(path, f"{column}: {len(errors)} values, not {VSD_TAUS}", line)
        return errors
    return parse_float(text, path, line, column)


def read_frames_csv(path):
    """frames.csv as a list of dicts, one per row: ints (frame, sensed_points, icp_iterations, icp_inliers,
    truth_points, truth_off_receiver, truth_off_surface, truth_on_propellers, truth_propellers_kept), a bool
    (icp_converged), strings (region, status),
    truth_error_by_fraction as ((count, error sum px), ...), vsd_errors as a tuple of 10 floats, floats
    elsewhere, None for an empty field."""
    path = Path(path)
    require_file(path, "frames.csv of an aar-analyze run")
    header, rows = read_csv(path)
    if header[0] != "frame":
        raise DataError(path, f"header starts with '{header[0]}', not 'frame'", 1)
    return [{c: _value(c, text, path, line) for c, text in row.items()} for line, row in rows]


class FrameDump:
    """What `aar-analyze run --dump-frames` wrote for one frame; `files` maps the kinds present (disparity,
    sensed, model, overlay, points) to their paths."""

    def __init__(self, folder, frame, files):
        self.folder = folder
        self.frame = frame
        self.files = files

    def __repr__(self):
        return f"<FrameDump {self.frame}: {', '.join(sorted(self.files))}>"

    def _path(self, kind, suffix):
        return self.files.get(kind, self.folder / f"{self.frame:06d}_{kind}.{suffix}")

    def disparity(self):
        """The colour-mapped disparity, H x W x 3 uint8, black where there is none."""
        return read_png(self._path("disparity", "png"))

    def overlay(self):
        """The left image with the registered model drawn over it, H x W x 3 uint8."""
        return read_png(self._path("overlay", "png"))

    def sensed(self):
        """The sensed cloud given to ICP, N x 3 [m], tanker frame."""
        return read_ply(self._path("sensed", "ply"))

    def model(self):
        """The reference model at the estimated pose, N x 3 [m], tanker frame."""
        return read_ply(self._path("model", "ply"))

    def points(self):
        """{column: float64 array} of NNNNNN_points.csv: u_px, v_px, disparity_px and, on datasets with depth
        truth, true_disparity_px (NaN where the pixel is not on the receiver)."""
        path = self._path("points", "csv")
        require_file(path, "written by --dump-frames for frames with sensed points")
        header, rows = read_csv(path)
        columns = {c: [parse_float(row[c], path, line, c) for line, row in rows] for c in header}
        return {c: np.array([np.nan if v is None else v for v in values], dtype=np.float64)
                for c, values in columns.items()}


class Run(FrameSequence):
    """A run folder; see `open_run`. A sequence of frames.csv's rows."""

    def __init__(self, path):
        self.path = Path(path)
        for name in REQUIRED:
            require_file(self.path / name, "every finished aar-analyze run writes it: "
                                           "is this a run folder, and did the run finish?")
        self.record = read_json(self.path / "run.json")
        self.frames = read_frames_csv(self.path / "frames.csv")
        analyzed = self.record.get("frames_analyzed")
        if analyzed != len(self.frames):
            raise DataError(self.path / "frames.csv", f"{len(self.frames)} rows, but run.json says {analyzed} "
                                                      "frames were analyzed (frames.csv of another run?)")

    def __repr__(self):
        return f"<Run {self.path}: {self.record.get('model')} model, {len(self.frames)} frames>"

    def column(self, name):
        """One column of frames.csv as a NumPy array: int64, bool, str, an object array of tuples for
        truth_error_by_fraction, float64 of shape (frames, 10) for vsd_errors and float64 for the rest
        (NaN where empty)."""
        if self.frames and name not in self.frames[0]:
            raise DataError(self.path / "frames.csv", f"has no column '{name}'")
        values = [row[name] for row in self.frames]
        if name in INT_COLUMNS:
            return np.array(values, dtype=np.int64)
        if name in BOOL_COLUMNS:
            return np.array(values, dtype=bool)
        if name in TEXT_COLUMNS:
            return np.array(values, dtype=str)
        if name == FRACTION_COLUMN:
            out = np.empty(len(values), dtype=object)
            out[:] = values
            return out
        if name == VSD_COLUMN:
            return np.array([[np.nan] * VSD_TAUS if v is None else v for v in values], dtype=np.float64
                            ).reshape(len(values), VSD_TAUS)
        return np.array([np.nan if v is None else v for v in values], dtype=np.float64)

    @cached_property
    def summary(self):
        """summary.json: statistics per group; everything outside its `timing` object is deterministic."""
        return read_json(self.path / "summary.json")

    @cached_property
    def calibration(self):
        """calibration.yaml, the calibration the run used (`read_calibration`; merged runs have none)."""
        return read_calibration(self.path / "calibration.yaml")

    @cached_property
    def calibration_report(self):
        """calibration_report.json, written when the run calibrated from the dataset's boards."""
        return read_json(self.path / "calibration_report.json")

    @cached_property
    def bop_results(self):
        """bop_results.csv as a list of dicts: scene_id, im_id, obj_id (ints), score, time [s] (floats),
        R (3 x 3) and t [mm] (3,) of the estimated camera_from_receiver."""
        path = self.path / "bop_results.csv"
        require_file(path, "the run's estimates in the BOP results format")
        header, rows = read_csv(path)
        out = []
        for line, row in rows:
            r = {k: _int(row[k], path, line, k) for k in ("scene_id", "im_id", "obj_id")}
            r["score"], r["time"] = (parse_float(row[k], path, line, k) for k in ("score", "time"))
            for key, shape in (("R", (3, 3)), ("t", (3,))):
                values = [parse_float(v, path, line, key) for v in row[key].split()]
                if len(values) != int(np.prod(shape)):
                    raise DataError(path, f"{key}: {len(values)} numbers, {int(np.prod(shape))} expected", line)
                r[key] = np.array(values).reshape(shape)
            out.append(r)
        return out

    def reference_cloud(self):
        """The reference model's points, N x 3 [m], receiver frame (reference_<model>.ply)."""
        return read_ply(self.path / f"reference_{self.record.get('model')}.ply")

    @cached_property
    def dumps(self):
        """{frame index: FrameDump} of the frames dumped with --dump-frames, in frame order."""
        folder = self.path / "frames"
        found = {}
        for path in sorted(folder.iterdir()) if folder.is_dir() else ():
            match = DUMP.fullmatch(path.name)
            if match:
                kind = match[2].partition(".")[0]
                found.setdefault(int(match[1]), {})[kind] = path
        return {frame: FrameDump(folder, frame, files) for frame, files in found.items()}


def open_run(path):
    """Opens the output folder `path` of `aar-analyze run` or `merge`.

    Reads run.json and frames.csv at once (raising DataError naming the
    file when run.json, frames.csv or summary.json is missing, or when
    frames.csv has another row count than run.json's frames_analyzed), the
    other files when first used.
    """
    return Run(path)
