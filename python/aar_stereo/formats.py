"""File formats shared by datasets and run folders: hashes, JSON, CSV, PNG, OpenEXR, PLY.

PIL and OpenImageIO are imported when an image is first read, so that poses,
calibrations and run tables need NumPy only.
"""

import csv
import hashlib
import json
import re
from pathlib import Path

import numpy as np

from .errors import DataError

SHA256_HEX = re.compile(r"[0-9a-f]{64}")


def sha256_file(path):
    """Hex SHA-256 of a file's bytes."""
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def check_hash(path, expected, source):
    """Raises DataError unless `path` exists and its SHA-256 is `expected` (`source` names who lists it)."""
    if not path.is_file():
        raise DataError(path, f"missing ({source} lists it)")
    if sha256_file(path) != expected:
        raise DataError(path, f"SHA-256 differs from {source}'s (file changed or truncated)")


def require_file(path, what):
    if not path.is_file():
        raise DataError(path, f"missing ({what})")


def read_json(path):
    """A JSON file as Python objects; DataError when missing or malformed."""
    require_file(path, "a JSON file is expected here")
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise DataError(path, f"malformed JSON: {e}") from None


def read_csv(path):
    """(header, [(line number, {column: text})]) of a CSV file with a header line."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if not header:
            raise DataError(path, "empty (a header line is expected)")
        rows = []
        for fields in reader:
            if len(fields) != len(header):
                raise DataError(path, f"{len(fields)} fields, the header has {len(header)}", reader.line_num)
            rows.append((reader.line_num, dict(zip(header, fields))))
    return header, rows


def parse_float(text, path, line, column):
    """A CSV field as a float; None when empty."""
    if text == "":
        return None
    try:
        return float(text)
    except ValueError:
        raise DataError(path, f"{column}: '{text}' is not a number", line) from None


def read_png(path):
    """A PNG as a NumPy array: H x W x 3 uint8 for RGB, H x W for grey (uint16 for 16-bit)."""
    from PIL import Image, UnidentifiedImageError

    path = Path(path)
    require_file(path, "an image is expected here")
    try:
        with Image.open(path) as image:
            pixels = np.array(image)
            # Pillow opens a 16-bit grey PNG (a thermal rig's radiometric view) as 32-bit mode "I".
            if image.mode.startswith("I") and image.format == "PNG" and pixels.max(initial=0) <= 0xFFFF:
                pixels = pixels.astype(np.uint16)
            return pixels
    except (UnidentifiedImageError, OSError) as e:
        raise DataError(path, f"unreadable image: {e}") from None


def read_exr(path):
    """A one-channel float32 OpenEXR image (the depth truth) as an H x W float32 array, via OpenImageIO."""
    import OpenImageIO as oiio

    path = Path(path)
    require_file(path, "an OpenEXR image is expected here")
    image = oiio.ImageInput.open(str(path))
    if image is None:
        raise DataError(path, f"unreadable OpenEXR image: {oiio.geterror()}")
    try:
        spec = image.spec()
        if spec.nchannels != 1:
            raise DataError(path, f"{spec.nchannels} channels {tuple(spec.channelnames)}, one (the depth) expected")
        pixels = image.read_image(0, 0, 0, 1, "float")
        if pixels is None:
            raise DataError(path, f"unreadable OpenEXR image: {image.geterror()}")
    finally:
        image.close()
    return pixels[:, :, 0]


_PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4", "uint": "<u4",
              "float": "<f4", "double": "<f8"}


def read_ply(path):
    """The vertices' x, y, z of a binary little-endian PLY (as aar-analyze writes) as an N x 3 float64 array."""
    path = Path(path)
    require_file(path, "a PLY file is expected here")
    data = path.read_bytes()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise DataError(path, "not a PLY file (no 'ply' and 'end_header' lines)")
    count, fields, element = None, [], None
    for line in data[:end].decode("ascii", "replace").splitlines()[1:]:
        words = line.split()
        if words[:1] == ["format"] and words[1:2] != ["binary_little_endian"]:
            raise DataError(path, f"format {' '.join(words[1:])}: only binary_little_endian is read")
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                count = int(words[2])
        if words[:1] == ["property"] and element == "vertex":
            if words[1] not in _PLY_TYPES:
                raise DataError(path, f"vertex property type '{words[1]}' not read (scalar properties only)")
            fields.append((words[2], _PLY_TYPES[words[1]]))
    names = [name for name, _ in fields]
    if count is None or names[:3] != ["x", "y", "z"]:
        raise DataError(path, "no vertex element with x, y, z as its first properties")
    dtype = np.dtype(fields)
    body = data[end + len(b"end_header\n"):]
    if len(body) < count * dtype.itemsize:
        raise DataError(path, f"truncated: {count} vertices announced, {len(body) // dtype.itemsize} present")
    vertices = np.frombuffer(body, dtype=dtype, count=count)
    return np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)


class FrameSequence:
    """len(), iteration and indexing over `self.frames`, in their order (a dataset's frames, a run's rows)."""

    def __len__(self):
        return len(self.frames)

    def __iter__(self):
        return iter(self.frames)

    def __getitem__(self, position):
        """The item at `position` in order (0 is the first, whatever its frame index)."""
        return self.frames[position]
