"""BLAZE-DEM's Figs. 18-19 redrawn with talus's numbers: the marbles and the corn-shaped
polyhedra of a slice through the hopper's middle, parallel to its front wall and projected on
it, at several instants after the outlet opens, coloured by the layer each began in (alternating
colours), and the share of each set through the outlet against time, with the measured and
Beverloo's rates.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
It also reads snapshots_<set>.csv and discharge_<set>.csv, which check.cpp writes beside
CHECKS_CSV.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402

SIDE, OUTLET = 0.176, 0.080  # m: the bin's side and the outlet's (check.cpp)
CONE = {"marbles": 0.0, "corn": (SIDE - OUTLET) / 2 * math.tan(math.radians(5))}
MARBLE = 0.016  # m, diameter
KERNEL_LENGTH, KERNEL_CROSS = 0.0125, 0.0067  # m: corn:0.017's length, mean cross-section
COLOURS = ("#2b5d9b", "#f0b429")  # alternate layers, as the paper's marbles
SETS = ("marbles", "corn")
# The slice drawn, |y| below this (m): two marble diameters, two of the corn grid's 11 mm columns.
# A slice shows the funnel that forms over the outlet; the front wall's layer moves little.
SLICE = {"marbles": MARBLE, "corn": 0.011}


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def draw_snapshot(ax, name, rows, top):
    # Seen from the front (looking along +y): the farthest drawn first.
    rows = sorted((r for r in rows if abs(float(r["y"])) < SLICE[name]),
                  key=lambda r: -float(r["y"]))
    x = [float(r["x"]) for r in rows]
    z = [float(r["z"]) for r in rows]
    colours = [COLOURS[int(r["layer"]) % 2] for r in rows]
    if name == "marbles":
        widths = heights = [MARBLE] * len(rows)
        angles = [0.0] * len(rows)
    else:  # the kernel's long axis as it shows on the front plane
        widths, heights, angles = [], [], []
        for r in rows:
            ax_, az = float(r["axis_x"]), float(r["axis_z"])
            widths.append(max(KERNEL_LENGTH * math.hypot(ax_, az), KERNEL_CROSS))
            heights.append(KERNEL_CROSS)
            angles.append(math.degrees(math.atan2(az, ax_)))
    ax.add_collection(EllipseCollection(widths, heights, angles, units="xy",
                                        offsets=list(zip(x, z)), transOffset=ax.transData,
                                        facecolors=colours, edgecolors="k", linewidths=0.2))
    # The bin: its walls, its floor down to the outlet's edges.
    cone = CONE[name]
    for s in (-1, 1):
        ax.plot([s * SIDE / 2, s * SIDE / 2, s * OUTLET / 2], [top, cone, 0], "k-", lw=1)
    ax.set_xlim(-SIDE / 2 - 0.01, SIDE / 2 + 0.01)
    ax.set_ylim(-0.1, top)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def main(argv):
    checks = {(r["quantity"], r["variant"]): r for r in read_checks(argv, __doc__)}
    folder = os.path.dirname(os.path.abspath(argv[1]))
    snapshots, series = {}, {}
    for name in SETS:
        for r in read_csv(os.path.join(folder, f"snapshots_{name}.csv")):
            snapshots.setdefault(name, {}).setdefault(float(r["time"]), []).append(r)
        series[name] = read_csv(os.path.join(folder, f"discharge_{name}.csv"))
    columns = max(len(v) for v in snapshots.values())
    fig = plt.figure(figsize=(2.1 * columns, 10))
    grid = fig.add_gridspec(3, columns, height_ratios=[1.3, 1.3, 1.2])
    for row, name in enumerate(SETS):
        times = sorted(snapshots[name])
        top = max(float(r["z"]) for r in snapshots[name][times[0]]) + 0.03
        for col, t in enumerate(times):
            ax = fig.add_subplot(grid[row, col])
            draw_snapshot(ax, name, snapshots[name][t], top)
            ax.set_title(f"{name}, t = {t:.2f} s", fontsize=8)
    ax = fig.add_subplot(grid[2, :])
    for i, name in enumerate(SETS):
        rows = series[name]
        n = int(rows[0]["bin"]) + int(rows[0]["stream"]) + int(rows[0]["removed"])
        mass = next((float(r["discharged_mass"]) / int(r["discharged"]) for r in rows
                     if int(r["discharged"]) > 0), 1.0)
        t = [float(r["time"]) for r in rows]
        f = [int(r["discharged"]) / n for r in rows]
        ax.plot(t, f, "-", color=f"C{i}", label=f"{name} ({n}, {n * mass:.3g} kg)")
        rate = checks.get((f"discharge_rate_{name}", name))
        if rate is None:
            continue
        # The measured rate and Beverloo's, as lines through the window's middle (32.5 %).
        mid = next(k for k, v in enumerate(f) if v >= 0.325)
        c = checks.get(("beverloo_coefficient", name))
        for key, style, what in (("measured", "--", "measured"), ("expected", ":", "Beverloo")):
            slope = float(rate[key])
            label = f"{name}: {what} {slope:.3g} kg/s"
            if what == "measured" and c:
                label += f" (C = {float(c['measured']):.2f})"
            span = [t[mid] - 0.3, t[mid] + 0.3]
            ax.plot(span, [f[mid] + slope / (n * mass) * (s - t[mid]) for s in span], style,
                    color=f"C{i}", label=label)
    ax.set_xlabel("time after the outlet opens (s)")
    ax.set_ylabel("share of the particles through the outlet")
    ax.set_ylim(0, 1)
    ax.legend(fontsize=8)
    save(fig, argv, "Hopper flow: marbles (Fig. 18) and corn (Fig. 19)")


if __name__ == "__main__":
    main(sys.argv)
