"""Datasets written by `aar-render render` and `aar-render calib` (docs/dataset-format.md)."""

import json
import re
from functools import cached_property
from hashlib import sha256
from pathlib import Path

import numpy as np

from .calibration import read_calibration
from .errors import DataError
from .formats import (SHA256_HEX, FrameSequence, check_hash, parse_float, read_csv, read_exr, read_json, read_png,
                      require_file)

SCHEMA = "aar-dataset/1"
MAX_FRAMES = 10 ** 7
# The input copies readers check against inputs.<key>.sha256 (docs/dataset-format.md, "Writing rules").
INPUT_COPIES = {"rig": "rig.json", "flight_path": "flightpath.csv", "receiver_model": "receiver.glb",
                "boom_model": "boom.glb", "boom_tube_model": "boom_tube.glb"}
# The inputs whose settings shape each kind of pair (the sidecars' settings_sha256).
SETTINGS_INPUTS = {"frame": ("rig", "receiver_model", "tanker_model", "flight_path", "boom_model", "boom_tube_model",
                             "propeller_model"),
                   "calib": ("rig", "board_model")}
SECTIONS = {"frame": ("frames", "frames"), "calib": ("calib", "calib")}  # kind -> (manifest section, folder)
SIDECAR = re.compile(r"(frames|calib)/(\d{6})\.json")


def pose_matrix(transform):
    """4 x 4 matrix of a JSON transform {"translation_m": [x, y, z], "rotation": 3 x 3 row-major}."""
    m = np.eye(4)
    m[:3, :3] = np.asarray(transform["rotation"], dtype=np.float64)
    m[:3, 3] = np.asarray(transform["translation_m"], dtype=np.float64)
    return m


def settings_sha256(manifest, kind):
    """SHA-256 of the render settings of `kind` ("frame" or "calib") as the manifest holds them: the compact
    JSON, keys sorted, of schema, device, image, that kind's section and inputs; None without the section."""
    section = SECTIONS[kind][0]
    if section not in manifest:
        return None
    settings = {key: manifest[key] for key in ("schema", "device", "image", section) if key in manifest}
    inputs = manifest.get("inputs", {})
    settings["inputs"] = {key: inputs[key] for key in SETTINGS_INPUTS[kind] if key in inputs}
    text = json.dumps(settings, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return sha256(text.encode()).hexdigest()


class Pair:
    """One rendered stereo pair: a frame of the flight path or a calibration board pose.

    The sidecar is read (and checked against the manifest) when first used;
    images are read on each call, after their SHA-256 is checked against the
    sidecar's and the manifest's.
    """

    def __init__(self, dataset, kind, index):
        self.dataset = dataset
        self.kind = kind
        self.index = index

    def __repr__(self):
        return f"<{type(self).__name__} {self.index} of {self.dataset.path}>"

    @property
    def sidecar_path(self):
        return self.dataset.path / SECTIONS[self.kind][1] / f"{self.index:06d}.json"

    @cached_property
    def sidecar(self):
        """The sidecar's JSON (docs/dataset-format.md, "Frame sidecar")."""
        return self.dataset.read_sidecar(self.kind, self.index)

    @property
    def files(self):
        """{name: path} of the pair's files (left, right, left_depth, left_mask, ...)."""
        return {name: self.dataset.path / ref["path"] for name, ref in self.sidecar["files"].items()}

    def read_file(self, name, reader):
        ref = self.sidecar["files"].get(name)
        if ref is None:
            raise DataError(self.sidecar_path, f"lists no '{name}' file (rendered without it: --depth, "
                                               "--depth-right)")
        path = self.dataset.path / ref["path"]
        check_hash(path, ref["sha256"], "the sidecar")
        listed = self.dataset.manifest["files"].get(ref["path"])
        if listed is not None and listed != ref["sha256"]:
            raise DataError(path, "SHA-256 differs from manifest.json's")
        return reader(path)

    def left(self):
        """The left image, H x W x 3 uint8 RGB (sRGB-encoded)."""
        return self.read_file("left", read_png)

    def right(self):
        """The right image, H x W x 3 uint8 RGB."""
        return self.read_file("right", read_png)

    @cached_property
    def poses(self):
        """{a_from_b: 4 x 4 matrix} of the truth the sidecar holds (docs/frames.md): tanker_from_left,
        tanker_from_right, right_from_left, and for frames tanker_from_receiver, left_from_receiver,
        right_from_receiver (with the boom tanker_from_boom, tanker_from_boom_tube), for boards tanker_from_board,
        left_from_board, right_from_board."""
        s = self.sidecar
        target = "receiver" if self.kind == "frame" else "board"
        poses = {f"tanker_from_{cam}": pose_matrix(s["rig"]["cameras"][cam]["tanker_from_camera"])
                 for cam in ("left", "right")}
        poses["right_from_left"] = pose_matrix(s["right_from_left"])
        poses[f"tanker_from_{target}"] = pose_matrix(s[f"tanker_from_{target}"])
        for cam in ("left", "right"):
            poses[f"{cam}_from_{target}"] = pose_matrix(s[f"cam_from_{target}"][cam])
        for part in ("boom", "boom_tube"):
            if f"tanker_from_{part}" in s.get("boom", {}):
                poses[f"tanker_from_{part}"] = pose_matrix(s["boom"][f"tanker_from_{part}"])
        return poses


class Frame(Pair):
    """A frame of the flight path: images, truth (`poses`, `sidecar`) and, with --depth, depth truth."""

    @property
    def time_s(self):
        return self.sidecar["time_s"]

    @property
    def region(self):
        """A, B, C or none (docs/frames.md, "Range and regions")."""
        return self.sidecar["region"]

    @property
    def range_m(self):
        return self.sidecar["range_m"]

    def depth(self, camera="left"):
        """Depth truth along the camera's optical axis [m], H x W float32, 0 where no surface was hit."""
        return self.read_file(f"{camera}_depth", read_exr)

    def mask(self, camera="left"):
        """Object ids, H x W uint8: 0 sky, 1 receiver, 2 tanker, 3 board, 4 ground, 5 cloud deck, 6 boom."""
        return self.read_file(f"{camera}_mask", read_png)

    def silhouette(self, camera="left"):
        """The receiver's whole silhouette, H x W uint8, 255 where it covers the pixel."""
        return self.read_file(f"{camera}_silhouette", read_png)


class CalibPair(Pair):
    """A calibration board pair: images and the board's pose (`poses`, `sidecar`)."""


class Dataset(FrameSequence):
    """A dataset folder; see `open_dataset`. A sequence of its frames in frame order."""

    def __init__(self, path, verify=True):
        self.path = Path(path)
        manifest_path = self.path / "manifest.json"
        require_file(manifest_path, f"no manifest: is '{self.path}' a dataset folder?")
        self.manifest = read_json(manifest_path)
        self._check_manifest(manifest_path)
        listed = {}
        for name in self.manifest["files"]:
            match = SIDECAR.fullmatch(name)
            if match:
                listed.setdefault(match[1], []).append(int(match[2]))
        self.frames = [Frame(self, "frame", i) for i in sorted(listed.get("frames", []))]
        self.calib_pairs = [CalibPair(self, "calib", i) for i in sorted(listed.get("calib", []))]
        self._by_index = {f.index: f for f in self.frames}
        if verify:
            self.verify()

    def _check_manifest(self, path):
        m = self.manifest
        if not isinstance(m, dict) or m.get("schema") != SCHEMA:
            raise DataError(path, f"schema {m.get('schema') if isinstance(m, dict) else None!r}, "
                                  f"'{SCHEMA}' expected")
        if not isinstance(m.get("files"), dict):
            raise DataError(path, "'files' must map relative paths to SHA-256")
        for name, digest in m["files"].items():
            if not isinstance(digest, str) or not SHA256_HEX.fullmatch(digest):
                raise DataError(path, f"files['{name}'] is not a SHA-256")
        for section in ("frames", "calib"):
            count = m.get(section, {}).get("count", 0)
            if not isinstance(count, int) or not 0 <= count <= MAX_FRAMES:
                raise DataError(path, f"{section}.count {count!r} is not an integer in [0, {MAX_FRAMES}]")
        if m.get("complete") and not m["files"]:
            raise DataError(path, "complete, but 'files' lists nothing")

    def verify(self):
        """Checks the whole dataset as aar-analyze and `sha256sum -c SHA256SUMS` would: every file the
        manifest lists against its SHA-256, the input copies against inputs.*.sha256, a complete manifest
        lists every frame and board pair, every sidecar is the pair it names, rendered with the manifest's
        settings, and lists its files with the manifest's hashes. Raises DataError naming the first bad file."""
        manifest_path = self.path / "manifest.json"
        files = self.manifest["files"]
        for name in sorted(files):
            check_hash(self.path / name, files[name], "manifest.json")
        for key, name in INPUT_COPIES.items():
            recorded = self.manifest.get("inputs", {}).get(key, {})
            if recorded.get("file") == name and "sha256" in recorded:
                check_hash(self.path / name, recorded["sha256"], f"manifest.json inputs.{key}")
        if self.manifest.get("complete"):
            for kind, (section, folder) in SECTIONS.items():
                for i in range(self.manifest.get(section, {}).get("count", 0)):
                    if f"{folder}/{i:06d}.json" not in files:
                        raise DataError(manifest_path, f"complete, but 'files' lacks {folder}/{i:06d}.json")
        for pair in self.frames + self.calib_pairs:
            for ref in pair.sidecar["files"].values():
                if files.get(ref["path"]) != ref["sha256"]:
                    raise DataError(pair.sidecar_path, f"lists {ref['path']} with another SHA-256 than "
                                                       "manifest.json (or manifest.json lacks it)")
        return self

    def read_sidecar(self, kind, index):
        """The JSON of frames/NNNNNN.json (kind "frame") or calib/NNNNNN.json ("calib"), checked against the
        manifest's SHA-256 and render settings."""
        folder = SECTIONS[kind][1]
        name = f"{folder}/{index:06d}.json"
        path = self.path / name
        if not path.is_file():
            raise DataError(path, "sidecar missing (not rendered)")
        if name in self.manifest["files"]:
            check_hash(path, self.manifest["files"][name], "manifest.json")
        s = read_json(path)
        if not isinstance(s, dict) or not isinstance(s.get("files"), dict) or not {"left", "right"} <= set(s["files"]):
            raise DataError(path, "malformed sidecar: no files.left and files.right")
        if s.get("kind") != kind or s.get("index") != index:
            raise DataError(path, f"holds {s.get('kind')} {s.get('index')}, not {kind} {index}")
        expected = settings_sha256(self.manifest, kind)
        if expected and s.get("settings_sha256", expected) != expected:
            raise DataError(path, "rendered with other settings than manifest.json records")
        return s

    def __repr__(self):
        return f"<Dataset {self.path}: {len(self.frames)} frames, {len(self.calib_pairs)} calibration pairs>"

    def frame(self, index):
        """The frame with flight-path index `index` (frames/NNNNNN.json)."""
        if index not in self._by_index:
            raise DataError(self.path / "manifest.json", f"lists no frame {index} (frames/{index:06d}.json)")
        return self._by_index[index]

    @property
    def frame_indices(self):
        return [f.index for f in self.frames]

    @property
    def image_size(self):
        """(width, height) of the images, pixels."""
        return self.manifest["image"]["width"], self.manifest["image"]["height"]

    def _input(self, name):
        path = self.path / name
        require_file(path, "the dataset's copy of its input")
        if name in self.manifest["files"]:
            check_hash(path, self.manifest["files"][name], "manifest.json")
        return path

    @cached_property
    def rig(self):
        """rig.json: the camera rig the dataset was rendered with (docs/dataset-format.md)."""
        return read_json(self._input("rig.json"))

    @cached_property
    def calibration(self):
        """calibration_ideal.yaml: the exact stereo calibration implied by the rig (`read_calibration`)."""
        return read_calibration(self._input("calibration_ideal.yaml"))

    @cached_property
    def flight_path(self):
        """flightpath.csv as a NumPy structured array, one row per sample, a float64 field per column
        (time_s, x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg and, with the boom, boom_*)."""
        path = self._input("flightpath.csv")
        header, rows = read_csv(path)
        values = [tuple(parse_float(row[c], path, line, c) for c in header) for line, row in rows]
        if any(v is None for row in values for v in row):
            raise DataError(path, "empty field (every field is a number)")
        return np.array(values, dtype=[(c, np.float64) for c in header])


def open_dataset(path, verify=True):
    """Opens the dataset folder `path` (written by aar-render).

    With `verify` (the default), first checks every file the manifest lists
    against its SHA-256, the sidecars against the manifest (see
    `Dataset.verify`); this reads the whole dataset once. Either way, each
    file read later is checked against its hashes as it is read. Raises
    DataError naming the file and the reason.
    """
    return Dataset(path, verify)
