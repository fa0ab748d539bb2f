"""Building blocks of the run report (report.py): HTML escaping, number
formatting and tables, figures inlined as SVG or PNG, the approach's regions
on a range axis, and the drawing of clouds and outlines over the left image.
"""

import base64
import html
import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The regions of the approach by range [m] (common/src/region.cpp), nearest first.
REGIONS = (("C", 32.0, 38.0), ("B", 38.0, 70.0), ("A", 70.0, 175.0))


def esc(value):
    return html.escape(str(value), quote=True)


def fmt(value, digits=4):
    """A value for a table cell: floats with `digits` significant digits, n/a for None and NaN."""
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return f"{value:.{digits}g}"
    return str(value)


def table(header, rows, caption=None):
    """An HTML table (without a header row when `header` is None); cells of numbers are right-aligned."""
    def cell(value):
        numeric = isinstance(value, (int, float, np.number)) and not isinstance(value, bool)
        return f'<td class="n">{esc(fmt(value))}</td>' if numeric else f"<td>{esc(fmt(value))}</td>"
    head = "<tr>" + "".join(f"<th>{esc(h)}</th>" for h in header) + "</tr>\n" if header else ""
    body = "".join("<tr>" + "".join(cell(v) for v in row) + "</tr>\n" for row in rows)
    title = f"<caption>{esc(caption)}</caption>" if caption else ""
    return f"<table>{title}{head}{body}</table>\n"


def flatten(value, prefix=""):
    """(dotted key, value) pairs of nested JSON objects, lists of numbers kept whole."""
    if isinstance(value, dict):
        return [pair for key, item in value.items() for pair in flatten(item, f"{prefix}{key}.")]
    if isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        return [pair for k, item in enumerate(value) for pair in flatten(item, f"{prefix}{k}.")]
    if isinstance(value, list):
        return [(prefix[:-1], " ".join(fmt(v, 6) for v in value))]
    return [(prefix[:-1], value)]


def figure(fig, alt, kind="svg"):
    """The figure as an inline <img>: SVG for plots, PNG for images; without dates or software versions."""
    buffer = io.BytesIO()
    metadata = {"Date": None, "Creator": None} if kind == "svg" else {"Software": None}
    fig.savefig(buffer, format=kind, metadata=metadata, dpi=100)
    plt.close(fig)
    mime = "image/svg+xml" if kind == "svg" else "image/png"
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f'<figure><img alt="{esc(alt)}" src="data:{mime};base64,{data}"></figure>\n'


def mark_regions(ax, ranges):
    """Dashed lines at the region boundaries inside the plotted ranges, the regions' letters on top."""
    finite = ranges[np.isfinite(ranges)]
    if finite.size == 0:
        return
    lo, hi = finite.min(), finite.max()
    pad = max(0.02 * (hi - lo), 0.05)
    ax.set_xlim(lo - pad, hi + pad)
    for name, start, end in REGIONS:
        for boundary in (start, end):
            if lo - pad < boundary < hi + pad:
                ax.axvline(boundary, color="0.4", linestyle="--", linewidth=0.8)
        if start <= hi and end >= lo:
            middle = (max(start, lo - pad) + min(end, hi + pad)) / 2
            ax.text(middle, 1.0, name, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                    fontweight="bold", color="0.3")


def project(points_in_camera, calibration):
    """Pixels (N x 2) of camera-frame points through M1 and D1 (k1 k2 p1 p2 k3, as aar-analyze's overlay);
    points behind the camera are dropped."""
    points = points_in_camera[points_in_camera[:, 2] > 0]
    x, y = points[:, 0] / points[:, 2], points[:, 1] / points[:, 2]
    k1, k2, p1, p2, k3 = np.append(calibration["D1"].ravel(), np.zeros(5))[:5]
    r2 = x * x + y * y
    radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3))
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    m = calibration["M1"]
    return np.column_stack([m[0, 0] * xd + m[0, 1] * yd + m[0, 2], m[1, 1] * yd + m[1, 2]])


def transform(matrix, points):
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def silhouette(pixels, size, radius):
    """The pixels' footprint as a float mask (H x W): each pixel grown to a square of 2 * radius + 1."""
    width, height = size
    mask = np.zeros((height, width), dtype=bool)
    u, v = np.round(pixels).astype(int).T
    inside = (u >= 0) & (u < width) & (v >= 0) & (v < height)
    mask[v[inside], u[inside]] = True
    mask = np.pad(mask, radius)  # so that np.roll wraps nothing but the padding
    for axis in (0, 1):
        grown = mask.copy()
        for shift in range(1, radius + 1):
            grown |= np.roll(mask, shift, axis) | np.roll(mask, -shift, axis)
        mask = grown
    return mask[radius:radius + height, radius:radius + width].astype(float)


def crop(drawn, size, margin=40):
    """(left, right, top, bottom) around the drawn pixels (1st to 99th percentile) with a margin, inside the
    image; the whole image when nothing is drawn."""
    width, height = size
    if not drawn:
        return 0, width, 0, height
    pixels = np.concatenate(drawn)
    lo, hi = np.percentile(pixels, 1, axis=0) - margin, np.percentile(pixels, 99, axis=0) + margin
    return max(lo[0], 0), min(hi[0], width), max(lo[1], 0), min(hi[1], height)
