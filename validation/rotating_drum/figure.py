"""The method paper's Fig. 15 redrawn with talus's numbers: (a) the last frame of the drum with
the particles that OpenCV found in it, (b) the velocity field from the tracked pictures and (c)
the same field from the DEM's own velocities, with R^2 between them.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
Reads fields.csv, detections.csv and frames/*.png beside CHECKS_CSV (check.cpp writes them).
"""
import csv
import glob
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main(argv):
    checks = {r["quantity"]: r for r in read_checks(argv, __doc__)}
    folder = os.path.dirname(os.path.abspath(argv[1]))
    fields = read_rows(os.path.join(folder, "fields.csv"))
    detections = read_rows(os.path.join(folder, "detections.csv"))
    frames = sorted(glob.glob(os.path.join(folder, "frames", "frame_*.png")))
    if not fields or not frames:
        sys.exit(f"{folder}: no fields.csv rows or no frames")

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2))
    image = plt.imread(frames[-1])
    axes[0].imshow(image)
    axes[0].plot([float(d["column"]) for d in detections], [float(d["row"]) for d in detections],
                 "+", color="crimson", markersize=5, label=f"{len(detections)} found")
    axes[0].set_title("(a) last frame, particles found", fontsize=9)
    axes[0].legend(fontsize=8, loc="upper right")
    axes[0].axis("off")

    speeds = []
    for source in ("image", "dem"):
        for r in fields:
            if int(r[f"n_{source}"]) >= 20:
                speeds.append(abs(complex(float(r[f"u_{source}"]), float(r[f"w_{source}"]))))
    scale = max(speeds) if speeds else 1.0
    for ax, source, name in ((axes[1], "image", "(b) tracked in the pictures"),
                             (axes[2], "dem", "(c) DEM truth")):
        rows = [r for r in fields if int(r[f"n_{source}"]) >= 20]
        a = [float(r["a"]) for r in rows]
        b = [float(r["b"]) for r in rows]
        u = [float(r[f"u_{source}"]) for r in rows]
        w = [float(r[f"w_{source}"]) for r in rows]
        speed = [abs(complex(x, y)) for x, y in zip(u, w)]
        q = ax.quiver(a, b, u, w, speed, cmap="viridis", clim=(0, scale), scale=scale * 12,
                      width=0.004)
        radius = max(abs(float(r["a"])) for r in fields) + 0.5 * (
            float(fields[1]["a"]) - float(fields[0]["a"]))
        ax.add_patch(plt.Circle((0, 0), radius, fill=False, color="0.4"))
        ax.set_aspect("equal")
        ax.set_xlim(-radius * 1.05, radius * 1.05)
        ax.set_ylim(-radius * 1.05, radius * 1.05)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
        ax.set_title(name, fontsize=9)
    fig.colorbar(q, ax=axes[2], label="speed (m/s)", shrink=0.8)

    def value(q):
        return float(checks[q]["measured"]) if q in checks else float("nan")

    axes[1].text(0.02, 0.02, f"R$^2$ = {value('velocity_r2'):.3f}\n"
                 f"repose {value('repose_angle'):.1f} deg (DEM {value('repose_angle_dem'):.1f})\n"
                 f"lift {value('highest_lift'):.1f} deg (DEM {value('highest_lift_dem'):.1f})",
                 transform=axes[1].transAxes, fontsize=8, va="bottom")
    save(fig, argv, "Quasi-2D rotating drum: velocity fields (method paper Fig. 15)")


if __name__ == "__main__":
    main(sys.argv)
