"""BLAZE-DEM's Fig. 15 redrawn with talus's numbers: the kinetic energy of a gravity packing of
octahedra against time, for the default volume law and BLAZE-DEM's linear law.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def main(argv):
    series, scalars = {}, {}
    for r in read_checks(argv, __doc__):
        if r["quantity"] == "kinetic_energy":
            series.setdefault(r["variant"], []).append(
                (float(r["parameter"]), float(r["measured"])))
        else:
            scalars[(r["quantity"], r["variant"])] = float(r["measured"])
    if not series:
        sys.exit(f"{argv[1]}: no kinetic energy rows")
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i, (law, data) in enumerate(sorted(series.items())):
        data.sort()
        gain = scalars.get(("energy_gain", law), float("nan"))
        fraction = scalars.get(("packing_fraction", law), float("nan"))
        count = scalars.get(("particles", law), float("nan"))
        ax.semilogy([d[0] for d in data], [max(d[1], 1e-16) for d in data], "-", color=f"C{i}",
                    label=f"{law} law, {count:,.0f} octahedra: balance rose by {100 * gain:.2g} % "
                          f"of the energy released; packing {fraction:.3f}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy (J)")
    ax.legend(fontsize=8)
    save(fig, argv, "Gravity packing")


if __name__ == "__main__":
    main(sys.argv)
