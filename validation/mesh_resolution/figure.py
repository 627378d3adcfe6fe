"""The method paper's Fig. 12 redrawn with talus's numbers: the contact force on a cube sliding
across plane walls meshed at several resolutions lambda, against kappa = dx / L_c.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    curves = {}
    with open(argv[1], newline="") as f:
        for r in csv.DictReader(f):
            key = (r["quantity"], r["variant"])
            curves.setdefault(key, []).append((float(r["parameter"]), float(r["measured"]),
                                               float(r["expected"]), r["verdict"]))
    if not curves:
        sys.exit(f"{argv[1]}: no rows")
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 7), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    variants = sorted({v for _, v in curves}, key=lambda v: float(v.split()[-1]))
    for i, variant in enumerate(variants):
        normal = sorted(curves.get(("normal_force", variant), []))
        tangential = sorted(curves.get(("tangential_force", variant), []))
        kappa = [d[0] for d in normal]
        top.plot(kappa, [d[1] for d in normal], "-", color=f"C{i}", lw=1.2,
                 label=f"$\\lambda$ = {variant.split()[-1]}")
        top.plot([d[0] for d in tangential], [d[1] for d in tangential], ":", color=f"C{i}",
                 lw=1)
        bottom.plot(kappa, [d[1] - d[2] for d in normal], "-", color=f"C{i}", lw=1)
    for ax in (top, bottom):
        ax.axvspan(1, 2, color="0.93", zorder=0)
    bottom.axhline(0.02, color="0.5", ls="--", lw=0.8)
    bottom.axhline(-0.02, color="0.5", ls="--", lw=0.8)
    top.set_ylabel("force / force scale (normal solid, friction dotted)")
    bottom.set_ylabel("normal force less $\\lambda$ = 16's")
    bottom.set_xlabel("$\\kappa = \\Delta x / L_c$ (shaded: wholly on the wall)")
    top.legend(fontsize=8, ncol=3)
    fig.suptitle(argv[3] if len(argv) > 3 else "Wall mesh resolution", fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)


if __name__ == "__main__":
    main(sys.argv)
