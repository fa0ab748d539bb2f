"""The one exception the package raises for bad or missing data."""


class DataError(Exception):
    """A file of a dataset or run folder is missing, changed or malformed.

    `path` is the file (a `pathlib.Path`), `line` its 1-based line where one
    is known, `reason` what is wrong; `str()` gives one line in the tools'
    style: `PATH:LINE: REASON` or `PATH: REASON`.
    """

    def __init__(self, path, reason, line=None):
        self.path = path
        self.reason = reason
        self.line = line
        where = f"{path}:{line}" if line is not None else f"{path}"
        super().__init__(f"{where}: {reason}")
