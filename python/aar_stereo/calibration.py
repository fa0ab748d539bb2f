"""Stereo calibrations in OpenCV FileStorage YAML (calibration_ideal.yaml, aar-analyze's calibration.yaml).

The subset FileStorage writes, read without OpenCV: an optional `%YAML:1.0`
and `---`, `#` comments, and per top-level key a number, a quoted string, a
flow sequence `[ a, b ]` or an `!!opencv-matrix` with indented `rows`,
`cols`, `dt` and `data: [ ... ]` (which may span lines).
"""

from pathlib import Path

import numpy as np

from .errors import DataError
from .formats import require_file

# OpenCV's FileStorage type letters.
_DTYPES = {"u": np.uint8, "c": np.int8, "w": np.uint16, "s": np.int16, "i": np.int32, "f": np.float32,
           "d": np.float64}
_SPECIAL = {".Inf": np.inf, "+.Inf": np.inf, "-.Inf": -np.inf, ".NaN": np.nan}


def _number(token, path, line):
    token = token.strip()
    if token in _SPECIAL:
        return float(_SPECIAL[token])
    try:
        return int(token)
    except ValueError:
        pass
    try:
        return float(token)
    except ValueError:
        raise DataError(path, f"'{token}' is not a number", line) from None


class _Lines:
    """The significant lines (number, text) of the file, consumed in order."""

    def __init__(self, text):
        self.items = [(n, line.rstrip()) for n, line in enumerate(text.splitlines(), 1)
                      if line.strip() and not line.strip().startswith("#")]
        self.at = 0

    def peek(self):
        return self.items[self.at] if self.at < len(self.items) else (None, None)

    def take(self):
        self.at += 1
        return self.items[self.at - 1]


def _sequence(first, lines, path, line):
    """The numbers of a flow sequence starting at `first` ("[ a, b,"), continued on the next lines until "]"."""
    text = first
    while "]" not in text:
        number, more = lines.peek()
        if number is None:
            raise DataError(path, "unterminated '[' sequence", line)
        lines.take()
        text += " " + more.strip()
    inside, _, rest = text.strip()[1:].partition("]")
    if rest.strip():
        raise DataError(path, f"unexpected '{rest.strip()}' after ']'", line)
    return [_number(t, path, line) for t in inside.split(",") if t.strip()]


def _matrix(lines, path, line):
    fields = {}
    while True:
        number, text = lines.peek()
        if number is None or not text[:1].isspace():
            break
        lines.take()
        key, sep, value = text.strip().partition(":")
        if not sep or key not in ("rows", "cols", "dt", "data") or key in fields:
            raise DataError(path, f"unexpected '{text.strip()}' in !!opencv-matrix", number)
        fields[key] = _sequence(value.strip(), lines, path, number) if key == "data" else value.strip()
    missing = [k for k in ("rows", "cols", "dt", "data") if k not in fields]
    if missing:
        raise DataError(path, f"!!opencv-matrix without {', '.join(missing)}", line)
    rows, cols = _number(fields["rows"], path, line), _number(fields["cols"], path, line)
    if fields["dt"] not in _DTYPES:
        raise DataError(path, f"dt '{fields['dt']}' is not a single-channel OpenCV type", line)
    if not (isinstance(rows, int) and isinstance(cols, int) and rows > 0 and cols > 0):
        raise DataError(path, f"rows {rows}, cols {cols}: positive integers expected", line)
    if len(fields["data"]) != rows * cols:
        raise DataError(path, f"{len(fields['data'])} data values for {rows} x {cols}", line)
    return np.array(fields["data"], dtype=_DTYPES[fields["dt"]]).reshape(rows, cols)


def read_calibration(path):
    """{key: value} of a calibration YAML: matrices (`M1`, `D1`, `M2`, `D2`, `R`, `T`, `R1`, `R2`, `P1`, `P2`,
    `Q`) as NumPy arrays of their `dt`, `image_size` as a tuple (width, height), numbers and strings as such.
    Raises DataError naming the file and line on anything else."""
    path = Path(path)
    require_file(path, "a calibration YAML is expected here")
    try:
        lines = _Lines(path.read_text(encoding="utf-8"))
    except UnicodeDecodeError as e:
        raise DataError(path, f"not UTF-8 text: {e}") from None
    if lines.peek()[1] is not None and lines.peek()[1].startswith("%YAML"):
        lines.take()
    if lines.peek()[1] == "---":
        lines.take()
    values = {}
    while lines.peek()[0] is not None:
        number, text = lines.take()
        key, sep, value = text.partition(":")
        value = value.strip()
        if text[:1].isspace() or not sep or not key:
            raise DataError(path, f"'{text.strip()}': a top-level 'key: value' expected", number)
        if key in values:
            raise DataError(path, f"duplicate key '{key}'", number)
        if value == "!!opencv-matrix":
            values[key] = _matrix(lines, path, number)
        elif value.startswith("["):
            values[key] = tuple(_sequence(value, lines, path, number))
        elif value[:1] in ("'", '"') and len(value) > 1 and value[-1] == value[0]:
            values[key] = value[1:-1]
        else:
            values[key] = _number(value, path, number)
    return values
