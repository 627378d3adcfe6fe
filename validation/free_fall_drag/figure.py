"""BLAZE-DEM section 5.1 redrawn with talus's numbers: a sphere's speed and drop under gravity
and quadratic drag against the closed forms, and the relative error at each time step.

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
    rows = {}
    with open(argv[1], newline="") as f:
        for r in csv.DictReader(f):
            rows.setdefault(r["quantity"], []).append(
                (float(r["parameter"]), float(r["measured"]), float(r["expected"])))
    if not rows:
        sys.exit(f"{argv[1]}: no rows")
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for name, data in sorted(rows.items()):
        data.sort()
        t = [d[0] for d in data]
        quantity, dt = name.split("_dt")
        ax = axes[0] if quantity == "speed" else axes[1]
        if dt == "1e-3":
            ax.plot(t, [d[2] for d in data], "k-", label="closed form")
        ax.plot(t, [d[1] for d in data], "o" if dt == "1e-3" else "+", mfc="none",
                label=f"talus, dt = {dt} s")
        axes[2].semilogy(t, [abs(d[1] - d[2]) / abs(d[2]) for d in data],
                         "o-" if quantity == "speed" else "s--", mfc="none",
                         label=f"{quantity}, dt = {dt} s")
    for ax, label in zip(axes, ("speed (m/s)", "drop (m)", "relative error")):
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    for bound, dt in ((1e-3, "1e-3"), (1e-4, "1e-4")):
        axes[2].axhline(bound, color="0.5", lw=0.8, ls=":")
        axes[2].text(0.02, bound * 1.1, f"paper's bound at dt = {dt} s", fontsize=7,
                     transform=axes[2].get_yaxis_transform())
    fig.suptitle(argv[3] if len(argv) > 3 else "Free fall with drag", fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)


if __name__ == "__main__":
    main(sys.argv)
