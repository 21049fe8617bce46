"""Figures of the fidelity report: distributions (fig. 4), heat maps (fig. 5), mesh statistics.

Every function returns a ``matplotlib.figure.Figure`` built without pyplot (no GUI backend, no
global state); the caller saves it. Distances are drawn in millimetres.

Heat maps draw the meshes themselves as shaded triangles coloured by the distance at each face's
centre (the meshes are subdivided first, so a large flat hull face shows how its distance varies).
Part frame (x along the part, y up, z out of the furniture) is drawn as plot (x, -z, y), a proper
rotation, so "up" is up on the page and the furniture front is behind the part.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib import colormaps
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import PowerNorm
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from realikea.sources import SOURCES

MM = 1000.0
SOURCE_COLORS = {"coacd": "#1f77b4", "hull": "#d62728"}
SOURCE_LABELS = {"coacd": "CoACD", "hull": "convex hull"}
CATEGORY_TITLES = {"knob": "knobs", "two_point": "two-point handles", "finger_pull": "finger pulls"}
FLOOR_MM = 1e-4  # log axes: smaller values (CoACD medians are often ~0) are drawn at this floor
HEAT_CMAP = "turbo"  # dark blue = precise, red = severe deviation (as in the paper)
HEAT_GAMMA = 0.5  # PowerNorm: small CoACD errors stay visible on a scale set by the hull
# (elevation, azimuth) in degrees per category: two-point handles and knobs from above and in
# front (the gap behind the bar, the neck under a knob's head); finger pulls from below and in
# front (the channel under the lip opens downwards)
VIEWS = {"knob": (15.0, -22.0), "two_point": (38.0, -68.0), "finger_pull": (-38.0, -64.0)}
RENDER_PIXELS = 1200  # side of the square image each heat-map panel is rendered into


def _jitter(n: int, width: float, seed: int) -> np.ndarray:
    return (np.random.default_rng(seed).random(n) - 0.5) * width


def distribution_figure(rows: Sequence[dict]) -> Figure:
    """Per category: box plots and per-part points of the mean, median and P90 of dist(q, P)."""
    categories = [c for c in CATEGORY_TITLES if any(r["category"] == c for r in rows)]
    stats = (("mean", "mean = E(Q→P)"), ("median", "median"), ("p90", "P90"))
    fig = Figure(figsize=(4.6 * len(categories) + 0.6, 4.8), layout="constrained")
    axes = fig.subplots(1, len(categories), sharey=True, squeeze=False)[0]
    all_values = [r[f"{s}_q_to_p_{k}_m"] * MM for r in rows for s in SOURCES for k, _ in stats]
    top = max(max(all_values, default=1.0), FLOOR_MM * 10) * 2.0
    for ax, category in zip(axes, categories, strict=True):
        group = [r for r in rows if r["category"] == category]
        clipped = 0
        for i, (stat, _) in enumerate(stats):
            for j, source in enumerate(SOURCES):
                values = np.array([r[f"{source}_q_to_p_{stat}_m"] for r in group]) * MM
                clipped += int(np.sum(values < FLOOR_MM))
                values = np.maximum(values, FLOOR_MM)
                x = i * 3.0 + j * 1.0
                color = SOURCE_COLORS[source]
                ax.boxplot(
                    values,
                    positions=[x],
                    widths=0.7,
                    showfliers=False,
                    patch_artist=True,
                    boxprops={"facecolor": color, "alpha": 0.25, "edgecolor": color},
                    medianprops={"color": color, "linewidth": 2},
                    whiskerprops={"color": color},
                    capprops={"color": color},
                )
                ax.scatter(
                    x + _jitter(len(values), 0.45, i * 2 + j),
                    values,
                    s=9,
                    color=color,
                    alpha=0.75,
                    linewidths=0,
                    zorder=3,
                    label=SOURCE_LABELS[source] if i == 0 else None,
                )
        ax.set_yscale("log")
        ax.set_ylim(FLOOR_MM / 1.6, top)
        ax.set_xticks([0.5, 3.5, 6.5], [label for _, label in stats])
        ax.set_xlim(-0.8, 7.8)
        ax.grid(axis="y", which="major", alpha=0.3)
        title = f"{CATEGORY_TITLES[category]} ({len(group)} parts)"
        ax.set_title(title)
        if clipped:
            ax.text(
                0.02,
                0.015,
                f"{clipped} values < {FLOOR_MM:g} mm drawn at the floor",
                transform=ax.transAxes,
                fontsize=7,
                color="0.35",
            )
    axes[0].set_ylabel("per-part dist(q, P) statistic (mm, log)")
    axes[0].legend(loc="upper left", fontsize=9)
    fig.suptitle("Collision-shell swelling dist(q, P): CoACD against the single convex hull")
    return fig


def _plot_coords(vertices: np.ndarray) -> np.ndarray:
    """Part frame (x, y, z) in metres to plot (x, -z, y) in millimetres."""
    v = np.asarray(vertices, dtype=float) * MM
    return np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])


def _light(elev: float, azim: float) -> np.ndarray:
    """A light from the camera, raised and turned a little (unit vector, plot frame)."""
    e, a = np.radians(elev + 25.0), np.radians(azim - 30.0)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def draw_triangles(ax, triangles, rgb, view, bounds) -> None:
    """Shaded triangles with one colour each on a 3D axes, orthographic, no axes drawn."""
    tris = _plot_coords(np.asarray(triangles).reshape(-1, 3)).reshape(-1, 3, 3)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    shade = 0.5 + 0.5 * np.abs(normals @ _light(*view))
    colors = np.clip(np.asarray(rgb)[:, :3] * shade[:, None], 0.0, 1.0)
    # edges in the face colour hide the anti-aliasing seams between neighbouring triangles
    ax.add_collection3d(
        Poly3DCollection(tris, facecolors=colors, edgecolors=colors, linewidths=0.3)
    )
    lo, hi = bounds
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo, zoom=0.7)  # a margin: a long box overflows at zoom 1
    ax.set_proj_type("ortho")
    ax.view_init(*view)
    ax.set_axis_off()


def render_triangles(triangles, rgb, view, bounds, pixels: int = RENDER_PIXELS) -> np.ndarray:
    """The triangles drawn alone on a white square image (``pixels`` wide, RGB uint8).

    A 3D axes is always square in its figure, so a long handle would fill a fraction of a wide
    panel; rendering apart and cropping the white margin lets the heat maps use their space.
    """
    fig = Figure(figsize=(pixels / 100, pixels / 100), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1), projection="3d")
    draw_triangles(ax, triangles, rgb, view, bounds)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy()


def _crop_box(images: Sequence[np.ndarray], pad: int = 6) -> tuple[slice, slice]:
    """The smallest box holding every non-white pixel of all images (same size), padded."""
    ink = np.any(np.stack([np.any(img < 250, axis=2) for img in images]), axis=0)
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    if len(rows) == 0:
        return slice(None), slice(None)
    h, w = ink.shape
    return (
        slice(max(rows[0] - pad, 0), min(rows[-1] + pad + 1, h)),
        slice(max(cols[0] - pad, 0), min(cols[-1] + pad + 1, w)),
    )


def heatmap_figure(category: str, heat_rows: Sequence) -> Figure:
    """A row per part: P, dist(p, Q) on P, dist(q, P) on the CoACD shell, dist(q', P) on the hull.

    All panels of a row share the view, the frame and one colour scale (0 to the largest distance
    of the row, square-root scaled), with a colorbar in millimetres.
    """
    view = VIEWS.get(category, (30.0, -60.0))
    cmap = colormaps[HEAT_CMAP]
    rendered = []
    for row in heat_rows:
        pts = np.vstack([_plot_coords(p.triangles.reshape(-1, 3)) for p in row.panels])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        bounds = (lo, hi)
        vmax = max(float(p.values.max()) * MM for p in row.panels if p.values is not None)
        norm = PowerNorm(HEAT_GAMMA, vmin=0.0, vmax=max(vmax, 1e-3))
        images = []
        for panel in row.panels:
            if panel.values is None:
                rgb = np.tile([0.78, 0.78, 0.8], (len(panel.triangles), 1))
            else:
                rgb = cmap(norm(panel.values * MM))
            images.append(render_triangles(panel.triangles, rgb, view, bounds))
        ys, xs = _crop_box(images)
        rendered.append((norm, [img[ys, xs] for img in images]))

    panel_width = 3.9  # inches
    # row height from the crop's shape; compact parts (knobs) are drawn a little smaller
    heights = [
        panel_width * float(np.clip(imgs[0].shape[0] / imgs[0].shape[1], 0.3, 0.75)) + 0.75
        for _, imgs in rendered
    ]
    fig = Figure(figsize=(4 * panel_width + 0.9, sum(heights) + 0.45), layout="constrained")
    grid = fig.add_gridspec(
        max(len(rendered), 1), 5, width_ratios=[1, 1, 1, 1, 0.04], height_ratios=heights or [1]
    )
    for i, (row, (norm, images)) in enumerate(zip(heat_rows, rendered, strict=True)):
        for k, (panel, image) in enumerate(zip(row.panels, images, strict=True)):
            ax = fig.add_subplot(grid[i, k])
            ax.imshow(image, interpolation="antialiased")
            ax.set_axis_off()
            title = f"({k + 1}) {panel.title}"
            if panel.mean is not None:
                title += f"\nmean {panel.mean * MM:.3g} mm, max {panel.values.max() * MM:.3g} mm"
            else:
                title = f"{row.part_id}: {row.label}\n{title}"
            ax.set_title(title, fontsize=9)
        cax = fig.add_subplot(grid[i, 4])
        fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), cax=cax, label="distance (mm)")
    fig.suptitle(
        f"Collision error heat maps, {CATEGORY_TITLES.get(category, category)}: "
        "dark blue = precise, red = severe deviation (colour scale per row)"
    )
    return fig


def _log_bins(values: Sequence[np.ndarray], count: int = 50, tail: float = 0.0) -> np.ndarray:
    """Log-spaced bin edges over the positive values, leaving out ``tail`` % at each end."""
    data = np.concatenate([np.asarray(v, dtype=float) for v in values])
    data = data[data > 0]
    lo, hi = np.percentile(data, [tail, 100.0 - tail])
    return np.geomspace(lo, hi, count + 1)


def mesh_stats_figure(rows: Sequence[dict], face_areas: dict[str, np.ndarray]) -> Figure:
    """Vertex counts per part, face-area distributions and CoACD pieces per part."""
    kinds = (
        ("visual", "visual mesh P", "0.3"),
        ("coacd", "CoACD pieces", SOURCE_COLORS["coacd"]),
        ("hull", "convex hull", SOURCE_COLORS["hull"]),
    )
    fig = Figure(figsize=(15.0, 4.4), layout="constrained")
    ax_v, ax_a, ax_p = fig.subplots(1, 3)

    counts = {key: np.array([r[f"{key}_vertices"] for r in rows], dtype=float) for key, *_ in kinds}
    bins = _log_bins(list(counts.values()), 30)
    for key, label, color in kinds:
        med = np.median(counts[key])
        ax_v.hist(counts[key], bins=bins, histtype="step", linewidth=1.8, color=color,
                  label=f"{label} (median {med:,.0f})")  # fmt: skip
    ax_v.set_xscale("log")
    ax_v.set_xlabel("vertices per part (CoACD: summed over pieces)")
    ax_v.set_ylabel("parts")
    ax_v.set_title("(a) vertex count per part")
    ax_v.legend(fontsize=8)

    areas = {key: np.asarray(face_areas[key], dtype=float) * 1e6 for key, *_ in kinds}
    # slivers reach 1e-10 mm²: the 0.1 % tails go into the end bins rather than set the axis
    bins = _log_bins(list(areas.values()), 60, tail=0.1)
    for key, label, color in kinds:
        a = np.clip(areas[key][areas[key] > 0], bins[0], bins[-1])
        weights = np.full(len(a), 1.0 / max(len(a), 1))
        ax_a.hist(a, bins=bins, weights=weights, histtype="step", linewidth=1.8, color=color,
                  label=f"{label} ({len(a):,} faces, median {np.median(a):.2g} mm²)")  # fmt: skip
    ax_a.set_xscale("log")
    ax_a.set_xlabel("face area (mm², log; 0.1 % tails in the end bins)")
    ax_a.set_ylabel("fraction of faces")
    ax_a.set_title("(b) face-area distribution, all parts")
    ax_a.legend(fontsize=8)

    categories = [c for c in CATEGORY_TITLES if any(r["category"] == c for r in rows)]
    pieces = [np.array([r["coacd_pieces"] for r in rows if r["category"] == c]) for c in categories]
    top = max((p.max() for p in pieces if len(p)), default=1)
    edges = np.arange(0.5, top + 1.5, max(1, int(np.ceil(top / 40))))
    ax_p.hist(pieces, bins=edges, stacked=True, label=[CATEGORY_TITLES[c] for c in categories],
              color=["#9467bd", "#2ca02c", "#ff7f0e"][: len(categories)])  # fmt: skip
    ax_p.set_xlabel("CoACD convex pieces per part")
    ax_p.set_ylabel("parts")
    ax_p.set_title("(c) CoACD decomposition size")
    ax_p.legend(fontsize=8)
    fig.suptitle("Mesh statistics of the interactive parts")
    return fig
