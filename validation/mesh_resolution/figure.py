"""The method paper's Fig. 12 redrawn with talus's numbers: the contact force on a cube sliding
across plane walls meshed at several resolutions lambda, against kappa = dx / L_c.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def main(argv):
    curves = {}
    for r in read_checks(argv, __doc__):
        curves.setdefault((r["quantity"], r["variant"]), []).append(
            (float(r["parameter"]), float(r["measured"]), float(r["expected"]), r["verdict"]))
    fig, (top, bottom, off) = plt.subplots(3, 1, figsize=(8, 10), sharex=True,
                                           gridspec_kw={"height_ratios": [3, 2, 2]})
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
        unweighted = sorted(curves.get(("normal_force_unweighted", variant), []))
        off.semilogy([d[0] for d in unweighted], [max(d[1], 1e-3) for d in unweighted], "-",
                     color=f"C{i}", lw=1)
    for ax in (top, bottom, off):
        ax.axvspan(1, 2, color="0.93", zorder=0)
    bottom.axhline(0.02, color="0.5", ls="--", lw=0.8)
    bottom.axhline(-0.02, color="0.5", ls="--", lw=0.8)
    top.set_ylabel("force / force scale (normal solid, friction dotted)")
    bottom.set_ylabel("normal force less $\\lambda$ = 16's")
    off.set_ylabel("normal force / force scale,\nwithout the area weights")
    off.set_ylim(1e-2, None)
    off.set_xlabel("$\\kappa = \\Delta x / L_c$ (shaded: wholly on the wall)")
    top.legend(fontsize=8, ncol=3)
    save(fig, argv, "Wall mesh resolution")


if __name__ == "__main__":
    main(sys.argv)
