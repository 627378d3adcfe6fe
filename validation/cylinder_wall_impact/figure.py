"""The method paper's Fig. 10 redrawn with talus's numbers: the cylinder's angular velocity and
normal velocity after a corner-first impact against Eqs. 27-28, over the impact angle.

usage: figure.py CHECKS_CSV OUTPUT_PNG [TITLE]   (talus validate runs it; Debian's matplotlib)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "framework"))
from figure_common import plt, read_checks, save  # noqa: E402


def main(argv):
    rows = {}
    for r in read_checks(argv, __doc__):
        rows.setdefault(r["quantity"], []).append(
            (float(r["parameter"]), float(r["measured"]), float(r["expected"]),
             float(r["tolerance"]), r["verdict"]))
    panels = [("omega_plus", "$\\omega_y^+$ (rad/s)", "Eq. 27"),
              ("v_z_plus", "$V_z^+$ (m/s)", "Eq. 28")]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, (name, label, equation) in zip(axes, panels):
        data = sorted(rows.get(name, []))
        if not data:
            sys.exit(f"{argv[1]}: no rows of {name}")
        theta = [d[0] for d in data]
        ax.plot(theta, [d[2] for d in data], "k-", label=equation)
        ax.fill_between(theta, [d[2] - d[3] for d in data], [d[2] + d[3] for d in data],
                        color="0.85", label="tolerance")
        for verdict, style in (("pass", "o"), ("fail", "x"), ("reported", "s")):
            pts = [d for d in data if d[4] == verdict]
            if pts:
                ax.plot([d[0] for d in pts], [d[1] for d in pts], style, mfc="none",
                        color={"pass": "tab:blue", "fail": "tab:red",
                               "reported": "tab:gray"}[verdict],
                        label=f"talus ({verdict})")
        ax.axhline(0, color="0.6", lw=0.5)
        ax.set_xlabel("impact angle $\\theta$ (degrees)")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    save(fig, argv, "Cylinder-wall impact")


if __name__ == "__main__":
    main(sys.argv)
