"""The method paper's section 3.3 with talus's numbers: each seed's bed height and their mean
against the paper's 16 cm, how still each bed is at the end, and each bed's picture (Fig. 13b;
bed_dt<step>_seed<seed>.png beside CHECKS_CSV, where talus drew them).

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import glob
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def main(argv):
    rows = {}
    for r in read_checks(argv, __doc__):
        rows.setdefault(r["quantity"], []).append(r)
    folder = os.path.dirname(os.path.abspath(argv[1]))
    beds = sorted(glob.glob(os.path.join(folder, "bed_dt*_seed*.png")))
    fig = plt.figure(figsize=(10, 7.5 if beds else 4))
    grid = fig.add_gridspec(2 if beds else 1, max(2, len(beds)),
                            height_ratios=[1, 1] if beds else [1])
    top = grid[0, :].subgridspec(1, 2)
    left = fig.add_subplot(top[0])
    right = fig.add_subplot(top[1])
    for k, path in enumerate(beds):
        ax = fig.add_subplot(grid[1, k])
        ax.imshow(plt.imread(path))
        ax.axis("off")
        match = re.search(r"bed_dt(.+)_seed(\d+)\.png$", path)
        ax.set_title(f"seed {match.group(2)}, dt {match.group(1)} s" if match else path,
                     fontsize=7)
    steps = sorted({q.split("_dt")[1] for q in rows if "_dt" in q})
    if not steps:
        sys.exit(f"{argv[1]}: no rows")
    for i, dt in enumerate(steps):
        heights = rows.get(f"bed_height_dt{dt}", [])
        seeds = [float(r["parameter"]) + 0.15 * i for r in heights]
        left.plot(seeds, [100 * float(r["measured"]) for r in heights], "o", mfc="none",
                  label=f"a seed, dt = {dt} s")
        for r in rows.get(f"mean_bed_height_dt{dt}", []):
            mean, tol = 100 * float(r["measured"]), 100 * float(r["tolerance"])
            left.axhline(mean, ls="--", color=f"C{i}", lw=1,
                         label=f"mean, dt = {dt} s ({r['verdict']})")
        rest = rows.get(f"kinetic_fraction_dt{dt}", [])
        right.semilogy([float(r["parameter"]) + 0.15 * i for r in rest],
                       [max(float(r["measured"]), 1e-16) for r in rest], "s", mfc="none",
                       label=f"dt = {dt} s")
        if rest:
            right.axhline(float(rest[0]["tolerance"]), color="0.5", ls=":", lw=1)
    left.axhspan(16 - tol, 16 + tol, color="0.9", label="paper: about 16 cm, tolerance")
    left.axhline(16, color="k", lw=1)
    left.set_xlabel("seed")
    left.set_ylabel("bed height (cm)")
    left.legend(fontsize=8)
    right.set_xlabel("seed")
    right.set_ylabel("kinetic energy at the end / released")
    right.legend(fontsize=8)
    save(fig, argv, "Dodecahedron packing")


if __name__ == "__main__":
    main(sys.argv)
