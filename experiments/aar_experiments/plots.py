"""Plots for the experiments (matplotlib, Agg backend).

Every function writes one PNG and returns its path. Inputs are plain lists, so
this module knows nothing about the analyzer's file formats. PNGs carry no
time stamp or software metadata, so the same data give the same bytes with
the same matplotlib.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Thesis regions of the CONOPS approach (docs/analysis.md) and the
# characterization range bins (thesis Tables 1-3).
REGION_EDGES_M = (32.0, 38.0, 70.0, 175.0)
BIN_EDGES_M = (20.0, 60.0, 110.0)

_MARKERS = ("o", "s", "^", "v", "D", "x")
_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110, metadata={"Software": None})
    plt.close(fig)
    return path


def _guides(ax, guides):
    """Vertical dashed lines at region or bin edges, with their labels."""
    if guides == "regions":
        for edge in REGION_EDGES_M:
            ax.axvline(edge, color="0.6", linestyle="--", linewidth=0.8)
        ymax = ax.get_ylim()[1]
        for label, lo, hi in (("C", 32, 38), ("B", 38, 70), ("A", 70, 175)):
            ax.text((lo + hi) / 2, ymax, label, ha="center", va="bottom", fontsize=8, color="0.4")
    elif guides == "bins":
        for edge in BIN_EDGES_M:
            ax.axvline(edge, color="0.6", linestyle="--", linewidth=0.8)


def scatter_vs_range(path, title, ylabel, series, guides=None, logy=False, zero_line=True):
    """One panel: each series is (label, ranges_m, values), drawn as markers.

    Like the thesis's error figures (15-18, 20-23, 26-32): error versus range
    from the left camera.
    """
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for k, (label, xs, ys) in enumerate(series):
        ax.scatter(xs, ys, s=9, marker=_MARKERS[k % len(_MARKERS)],
                   color=_COLORS[k % len(_COLORS)], label=label, linewidths=0.5)
    if zero_line and not logy:
        ax.axhline(0.0, color="black", linewidth=0.6)
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel("range from the left camera (m)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, linewidth=0.3)
    _guides(ax, guides)
    if series:
        ax.legend(fontsize=8, loc="best")
    return _save(fig, path)


def panels_vs_range(path, title, panels, guides=None, shade=None):
    """Several stacked panels sharing the range axis.

    panels: list of (ylabel, series) or (ylabel, series, (ymin, ymax)), series
    as in scatter_vs_range.
    shade: optional (lo_m, hi_m, label) band drawn on every panel.
    """
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.6 * len(panels) + 0.6), sharex=True)
    if len(panels) == 1:
        axes = [axes]
    for ax, panel in zip(axes, panels):
        ylabel, series = panel[0], panel[1]
        if len(panel) > 2:
            ax.set_ylim(*panel[2])
        for k, (label, xs, ys) in enumerate(series):
            ax.scatter(xs, ys, s=9, marker=_MARKERS[k % len(_MARKERS)],
                       color=_COLORS[k % len(_COLORS)], label=label, linewidths=0.5)
        if shade:
            ax.axvspan(shade[0], shade[1], color="tab:red", alpha=0.12, label=shade[2])
        ax.set_ylabel(ylabel)
        ax.grid(True, linewidth=0.3)
        _guides(ax, guides)
        ax.legend(fontsize=8, loc="best")
    axes[0].set_title(title, fontsize=10)
    axes[-1].set_xlabel("range from the left camera (m)")
    return _save(fig, path)


def panels_vs_x(path, title, xlabel, panels, edges=(), shades=(), xlim=None, lines=False):
    """Several stacked panels sharing an arbitrary x axis (frame index, or a range interval).

    panels: list of (ylabel, series) or (ylabel, series, (ymin, ymax)); a series is (label, xs, ys) or
    (label, xs, ys, colour). edges: (x, label) vertical dashed lines, labelled at the top of the first panel
    (region boundaries). shades: (lo, hi, label) bands drawn on every panel. lines: join each series' points.
    """
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 1.9 * len(panels) + 0.9), sharex=True)
    if len(panels) == 1:
        axes = [axes]
    for i, (ax, panel) in enumerate(zip(axes, panels)):
        ylabel, series = panel[0], panel[1]
        for k, s in enumerate(series):
            label, xs, ys = s[0], s[1], s[2]
            color = s[3] if len(s) > 3 else _COLORS[k % len(_COLORS)]
            if lines:
                ax.plot(xs, ys, color=color, linewidth=0.6, alpha=0.7)
            ax.scatter(xs, ys, s=7, marker=_MARKERS[k % len(_MARKERS)], color=color, label=label,
                       linewidths=0.5)
        if len(panel) > 2:
            ax.set_ylim(*panel[2])
        elif not ylabel.startswith("fraction"):
            ax.axhline(0.0, color="black", linewidth=0.6)
        for k, (lo, hi, label) in enumerate(shades):
            ax.axvspan(lo, hi, color=("tab:red", "tab:gray")[k % 2], alpha=0.12, label=label if i == 0 else None)
        for x, label in edges:
            ax.axvline(x, color="0.5", linestyle="--", linewidth=0.8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.tick_params(labelsize=8)
        ax.grid(True, linewidth=0.3)
    if xlim:
        axes[0].set_xlim(*xlim)
    lo, hi = axes[0].get_xlim()
    ymax = axes[0].get_ylim()[1]
    for x, label in edges:
        if lo <= x <= hi:
            axes[0].text(x, ymax, " " + label, ha="left", va="bottom", fontsize=7, color="0.35")
    axes[0].legend(fontsize=7, loc="lower left", ncol=2)
    if len(axes) > 1 and len(panels[1][1]) > 1:
        axes[1].legend(fontsize=7, loc="best")
    axes[0].set_title(title, fontsize=10, pad=14)
    axes[-1].set_xlabel(xlabel)
    return _save(fig, path)


def grouped_bars(path, title, ylabel, categories, series, logy=False, hline=None, rotation=0, figsize=(8, 4.5)):
    """Grouped bars: series is a list of (label, values per category); hline: a reference level drawn across
    (a ratio's 1); rotation: of the category labels (deg)."""
    fig, ax = plt.subplots(figsize=figsize)
    n = max(len(series), 1)
    width = 0.8 / n
    for k, (label, values) in enumerate(series):
        xs = [i + (k - (n - 1) / 2) * width for i in range(len(categories))]
        ys = [v if v is not None else 0.0 for v in values]
        ax.bar(xs, ys, width=width, label=label, color=_COLORS[k % len(_COLORS)])
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels(categories, rotation=rotation, ha="right" if rotation else "center")
    if hline is not None:
        ax.axhline(hline, color="black", linewidth=0.8)
    if logy:
        ax.set_yscale("log")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, axis="y", linewidth=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def crop_to_green(source, path, min_size=(320, 240)):
    """Copies the PNG `source` to `path`, cropped to its pure-green pixels (the drawn model of an
    `aar-analyze run --dump-frames` overlay) with a margin of half their extent, at least `min_size`
    (width, height) px; the whole image when it has none."""
    import matplotlib.image as mpimg
    import numpy as np

    image = mpimg.imread(source)[:, :, :3]
    green = np.argwhere((image[:, :, 0] == 0) & (image[:, :, 1] == 1) & (image[:, :, 2] == 0))
    if len(green):
        (y0, x0), (y1, x1) = green.min(axis=0), green.max(axis=0) + 1
        half_w = max((x1 - x0) // 2 + (x1 - x0) // 4, min_size[0] // 2)
        half_h = max((y1 - y0) // 2 + (y1 - y0) // 4, min_size[1] // 2)
        cx, cy = (x0 + x1) // 2, (y0 + y1) // 2
        image = image[max(0, cy - half_h):cy + half_h, max(0, cx - half_w):cx + half_w]
    mpimg.imsave(path, image, metadata={"Software": None})
    return path
