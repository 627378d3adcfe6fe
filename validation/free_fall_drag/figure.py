"""BLAZE-DEM section 5.1 redrawn with talus's numbers: a sphere's speed and drop under gravity
and quadratic drag against the closed forms, and the relative error at each time step.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def main(argv):
    rows = {}
    for r in read_checks(argv, __doc__):
        rows.setdefault((r["quantity"], r["variant"]), []).append(
            (float(r["parameter"]), float(r["measured"]), float(r["expected"])))
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
    save(fig, argv, "Free fall with drag")


if __name__ == "__main__":
    main(sys.argv)
