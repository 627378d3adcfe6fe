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
            rows.setdefault((r["quantity"], r.get("variant", "")), []).append(
                (float(r["parameter"]), float(r["measured"]), float(r["expected"])))
    if not rows:
        sys.exit(f"{argv[1]}: no rows")
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    drawn = set()
    for (name, solver), data in sorted(rows.items()):
        data.sort()
        t = [d[0] for d in data]
        quantity, dt = name.split("_dt")
        ax = axes[0] if quantity == "speed" else axes[1]
        if quantity not in drawn:
            ax.plot(t, [d[2] for d in data], "k-", label="closed form")
            drawn.add(quantity)
        marker = {"1e-3": "o", "1e-4": "+"}.get(dt, "x") if solver != "reference" else "^"
        ax.plot(t, [d[1] for d in data], marker, mfc="none",
                label=f"talus {solver}, dt = {dt} s".replace("  ", " "))
        axes[2].semilogy(t, [max(abs(d[1] - d[2]) / abs(d[2]), 1e-17) for d in data],
                         ("o-" if quantity == "speed" else "s--") if solver != "reference"
                         else ("^:" if quantity == "speed" else "v:"), mfc="none",
                         label=f"{quantity}, {solver}, dt = {dt} s")
    for ax, label in zip(axes, ("speed (m/s)", "drop (m)", "relative error")):
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label)
        ax.legend(fontsize=7, loc="lower left" if ax is axes[2] else "best")
    for bound, dt in ((1e-3, "1e-3"), (1e-4, "1e-4")):
        axes[2].axhline(bound, color="0.5", lw=0.8, ls=":")
        axes[2].text(0.02, bound * 1.1, f"paper's bound at dt = {dt} s", fontsize=7,
                     transform=axes[2].get_yaxis_transform())
    fig.suptitle(argv[3] if len(argv) > 3 else "Free fall with drag", fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)


if __name__ == "__main__":
    main(sys.argv)
