"""The thesis's layout (components, regions, range bins, MSAA levels) and its numbers.

The numbers live in experiments/thesis_tables.json, typed from Parsons (2017),
chapter IV and Appendices A and B, each with its table, row and column.
Component order: X (m), Y (m), Z (m), Roll, Pitch, Yaw (deg). None = not
reported. "diff" rows are the thesis's printed "Difference (%)" rows. Nothing
in THESIS is ever used as one of OUR numbers.
"""

import json
from pathlib import Path

COMPONENTS = ("x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg")
COMPONENT_HEADERS = ("X (m)", "Y (m)", "Z (m)", "Roll (deg)", "Pitch (deg)", "Yaw (deg)")
REGIONS = ("A", "B", "C")
REGION_RANGES = {"A": "70-175 m", "B": "38-70 m", "C": "32-38 m"}
BINS = ("20-60", "60-110")
MSAA_LEVELS = (1, 4, 8, 16, 32)

TABLES_JSON = Path(__file__).resolve().parent.parent / "thesis_tables.json"


def _json_key(key):
    """Row and column keys as the reports index them: [i, j] becomes (i, j); strings and ints stay."""
    return tuple(key) if isinstance(key, list) else key


def load(path=TABLES_JSON):
    """{table: nested rows} from thesis_tables.json.

    A row is nested under its `index` keys, in order. Its value: `value` as
    is; else `values`, as a tuple in column order when the columns are names
    (x_m, ..., mean_s, ...), or as {column: value} when they are keys (MSAA
    levels, Q elements).
    """
    with open(path) as f:
        tables = json.load(f)["tables"]
    thesis = {}
    for name, table in tables.items():
        nested = thesis.setdefault(name, {})
        columns = table.get("columns")
        for row in table["rows"]:
            keys = [_json_key(row[k]) for k in table["index"]]
            if "value" in row:
                value = row["value"]
            else:
                if len(row["values"]) != len(columns):
                    raise ValueError(f"{path}: {name}, row {keys}: {len(row['values'])} values for "
                                     f"{len(columns)} columns")
                if all(isinstance(c, str) for c in columns):
                    value = tuple(row["values"])
                else:
                    value = {_json_key(c): v for c, v in zip(columns, row["values"])}
            d = nested
            for k in keys[:-1]:
                d = d.setdefault(k, {})
            if keys[-1] in d:
                raise ValueError(f"{path}: {name}: row {keys} appears twice")
            d[keys[-1]] = value
    return thesis


THESIS = load()
