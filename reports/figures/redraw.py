#!/usr/bin/python3
"""The papers' figures redrawn in one style from what `talus validate` wrote, each beside the
numbers the paper gives for it, with an index (README.md) that names the run behind each figure.

usage: redraw.py [--output DIR] [--provenance FILE] RESULTS_DIR [RESULTS_DIR ...]
                 [--scaling FILE [FILE ...]]

RESULTS_DIR is an output directory of `talus validate` (validation-results.json, and per case
<case>/checks.csv with what else the case writes). Where several hold a case, a full version is
drawn before a small one, then the directory given last. A directory without
validation-results.json, or a case that no directory holds, is reported on stderr in one line;
the figures that can be drawn are drawn and the index says which are missing and why. Exit
status 0 when every figure was drawn and every directory read, 1 otherwise, 2 for a bad command
line or provenance file. reports/README.md, "reports/figures", says more.

--scaling FILE draws the method paper's Figs. 17-18 too, from scaling.json files that
experiments/scaling/run_scaling.py writes on the CUDA backend: the parallel efficiency of its
rows timed after the run's setup (those with timed_steps) on no more ranks than the machine has
GPUs. Give it after the directories (or end its files with --). A scaling file that is missing,
not JSON or not as run_scaling.py writes it is refused in one line (exit 2); one without a row to
draw is reported in one line and the figure drawn without it (exit 1).

The papers: the method paper (large-scale multiple-GPU DEM of polyhedral particles) and
BLAZE-DEM. Their copies hold the figures as pictures only, so no value is digitised from a
picture here: the numbers drawn as the paper's are those its text and tables give, each with a
comment naming where.
"""
import argparse
import csv
import glob
import importlib.util
import io
import math
import os
import re
import shlex
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "validation", "framework"))
sys.path.insert(0, os.path.join(ROOT, "reports"))
from figure_common import plt, read_checks  # noqa: E402
import generate  # noqa: E402  (its JSON reading, provenance, number format and atomic writes)
from PIL import Image  # noqa: E402  (Debian's python3-pil, which matplotlib needs)

# ---- The papers' numbers ------------------------------------------------------------------
# Method paper, §3.1, Table 1 ("Parameters in the cylindrical particle and wall impact
# simulation"): D = 8e-3 m, L = 5.3e-3 m, V = 2.62e-7 m^3, rho = 1245 kg/m^3,
# I_yy = 2.047e-9 kg m^2, e = 0.85. Fig. 10 itself is a picture; its analytical curves are
# Eqs. 27-28 evaluated with these (r: centre to the rim corner C; alpha: the face to the line to C).
TABLE1 = {"D": 8e-3, "L": 5.3e-3, "V": 2.62e-7, "rho": 1245.0, "I_yy": 2.047e-9, "e": 0.85}
# The impact speed: the paper gives none (Eqs. 27-28 are linear in it); talus's case falls at
# 1 m/s (validation/cylinder_wall_impact/README.md).
IMPACT_SPEED = 1.0
# Method paper, §3.3, on Fig. 13: "The final packing height in both the experiment and the
# simulation was approximately 16 cm."
PAPER_BED_HEIGHT_CM = 16.0
# Method paper, §3.4, on Fig. 15 (b, c): the simulated and experimental velocity fields
# correlate "with a correlation coefficient of R^2 = 0.8". It gives no angle of repose or lift.
PAPER_DRUM_R2 = 0.8
# BLAZE-DEM, §5.1, on Fig. 13 (alpha = 0.5): "the numerical error bound at 0.10% for a step size
# of 10^-3 and 0.010% for a step size of 10^-4".
PAPER_FALL_BOUNDS = {"1e-3": 1e-3, "1e-4": 1e-4}
# BLAZE-DEM, §5.2: a 128 x 128 x 64 grid of polyhedra, shown at the start and "after 1 second"
# (Fig. 14); Fig. 15 plots their kinetic energy, a picture with no number in the text.
PAPER_PACKING_COUNT = 128 * 128 * 64
PAPER_PACKING_TIME = 1.0
# BLAZE-DEM, §5.3: 836 marbles (Fig. 18) and 13,824 corn-shaped polyhedra (Fig. 19) discharge
# from a square hopper over 5 s; pictures compared by eye, no dimensions, sizes or rates.
PAPER_HOPPER_FIGURE = {"marbles": 18, "corn": 19}
# Method paper, §3.5, Figs. 17-18 (no table): the strong-scaling efficiency "remains above 85% up
# to 16 GPUs" (Fig. 17); with 5.0e6 particles a GPU the weak-scaling efficiency drops "to
# approximately 85% at 16 GPUs" (Fig. 18 b). Drawn as statements: a line over 1-16 GPUs, a point.
PAPER_SCALING_TEXT = ("Fig. 17: the parallel efficiency \"remains above 85% up to 16 GPUs\"; "
                      "Fig. 18 (b): with 5.0e6 particles a GPU it drops \"to approximately 85% "
                      "at 16 GPUs\" (section 3.5)")
PAPER_EFFICIENCY, PAPER_GPUS, PAPER_WEAK_PER_GPU = 0.85, 16, 5.0e6
# The sizes of the paper's scaling runs, used only to say which are still to be run: weak
# scaling at 1.0e6, 2.0e6 and 5.0e6 particles a GPU (docs/parallel.md: "1 to 5 million particles
# a GPU"), strong scaling of 2.0e7 particles.
PAPER_WEAK_COUNTS, PAPER_STRONG_TOTALS = (1.0e6, 2.0e6, 5.0e6), (2.0e7,)

# ---- One style --------------------------------------------------------------------------
STYLE = {"savefig.dpi": 100, "font.size": 8, "axes.titlesize": 9, "axes.labelsize": 8,
         "legend.fontsize": 7, "xtick.labelsize": 7, "ytick.labelsize": 7, "axes.grid": True,
         "grid.color": "0.9", "grid.linewidth": 0.6, "axes.spines.top": False,
         "axes.spines.right": False, "lines.linewidth": 1.2, "lines.markersize": 4,
         "legend.frameon": False}
PAPER = "k"                        # the paper's numbers
BAND = "0.88"                      # tolerances
VERDICT = {"pass": "tab:blue", "fail": "tab:red", "reported": "tab:gray"}
MARK = {"pass": "o", "fail": "x", "reported": "s"}
WIDTH = 10.0                       # inches; at 100 dpi a figure is 1000 px wide


class Missing(Exception):
    """What a figure lacks: the one line that says so on stderr and in the index."""


# ---- Reading the runs -------------------------------------------------------------------
class Run:
    """One RESULTS_DIR: validation-results.json's commit, backend and version; the machine and
    command where it records them, else where the provenance file gives them."""

    def __init__(self, order, directory, data, given):
        self.id, self.order, self.dir, self.data = f"R{order}", order, directory, data
        self.cases = {c["case"]: c for c in data["cases"]}
        self.commit = str(data["commit"])
        self.backend, self.version = str(data["backend"]), str(data["version"])
        self.machine = str(data.get("machine") or given.get("machine") or "not recorded")
        self.command = str(data.get("command") or given.get("command") or "not recorded")
        self.used = []

    def path(self, case, *names):
        return os.path.join(self.dir, case, *names)

    def footer(self):
        return (f"talus: {self.version} version on the {self.backend} backend, commit "
                f"{self.commit}, {self.machine} (run {self.id}: {self.dir})")


def read_runs(directories, provenance):
    runs, problems = [], []
    for order, directory in enumerate(directories, 1):
        path = os.path.join(directory, "validation-results.json")
        if not os.path.isfile(path):
            problems.append(f"{directory}: no validation-results.json (not an output directory "
                            "of talus validate); skipped")
            continue
        try:
            data = generate.read_validation(path)
        except generate.Refusal as e:
            problems.append(f"{e}; skipped")
            continue
        given = (generate.provenance_entry(provenance, directory)
                 or generate.provenance_entry(provenance, os.path.normpath(directory)))
        runs.append(Run(order, directory, data, given))
    return runs, problems


def case_rows(runs, case):
    """(run, checks.csv rows) of the run that draws `case`: a full version before a small one,
    then the directory given last. Missing when none holds it."""
    holding = sorted((r for r in runs if case in r.cases),
                     key=lambda r: (r.version == "full", r.order), reverse=True)
    if not holding:
        raise Missing(f"no results directory holds {case}")
    reasons = []
    for run in holding:
        path = run.path(case, "checks.csv")
        if not os.path.isfile(path):
            reasons.append(f"{path} is missing")
            continue
        try:
            return run, read_checks(["redraw", path, ""], f"{path}: unreadable")
        except SystemExit as e:  # figure_common's message: the file holds no rows
            reasons.append(str(e))
    raise Missing("; ".join(reasons))


def by(rows, *keys):
    """Rows grouped by the values of `keys` (a tuple, or the value alone for one key)."""
    groups = {}
    for r in rows:
        k = tuple(r[key] for key in keys)
        groups.setdefault(k if len(k) > 1 else k[0], []).append(r)
    return groups


def f(r, key):
    return float(r[key])


def error(r):
    return abs(f(r, "measured") - f(r, "expected"))


def read_csv(path):
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


def case_module(case):
    """validation/<case>/figure.py as a module, for what it draws that is worth reusing."""
    spec = importlib.util.spec_from_file_location(
        f"{case}_figure", os.path.join(ROOT, "validation", case, "figure.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def checked_summary(rows, what, unit, where):
    """'what: n of m checked within their tolerance; the worst x unit off (tolerance t unit) at
    where p': the worst is the row of largest error over its tolerance."""
    checked = [r for r in rows if r["verdict"] in ("pass", "fail")]
    if not checked:
        return f"{what}: nothing checked"
    worst = max(checked, key=lambda r: error(r) / max(f(r, "tolerance"), 1e-300))
    passed = sum(r["verdict"] == "pass" for r in checked)
    return (f"{what}: {passed} of {len(checked)} checked within their tolerance; the worst "
            f"{generate.fmt(error(worst))}{unit} off (tolerance "
            f"{generate.fmt(f(worst, 'tolerance'))}{unit}) at {where} "
            f"{generate.fmt(f(worst, 'parameter'))}")


# ---- The figures --------------------------------------------------------------------------
def new_figure(height, columns=1, **grid):
    fig = plt.figure(figsize=(WIDTH, height))
    return fig, fig.add_gridspec(1, columns, **grid)


def finish(fig, spec, run, paper_note):
    fig.suptitle(f"{spec['paper']} {spec['number']}: {spec['title']}", fontsize=10, x=0.01,
                 ha="left")
    height = fig.get_figheight()  # inches: the footer takes 0.4 of them, the title 0.3
    footer = "; ".join(r.footer() for r in (run if isinstance(run, list) else [run]))
    fig.text(0.01, 0.22 / height, footer, fontsize=6.5, color="0.3")
    fig.text(0.01, 0.06 / height, "paper: " + paper_note, fontsize=6.5, color="0.3")
    for _ in range(2):  # twice: the first pass sees equal-aspect panels at their full size
        fig.tight_layout(rect=(0, 0.4 / height, 1, 1 - 0.3 / height))


def eqs_27_28(theta_deg):
    """Eqs. 27-28 with Table 1's cylinder: (omega_y+, V_z+) after a corner-first impact at 1 m/s."""
    t = TABLE1
    m, r = t["rho"] * t["V"], math.hypot(t["D"] / 2, t["L"] / 2)
    alpha = math.atan2(t["L"] / 2, t["D"] / 2)
    arm = r * math.cos(alpha + math.radians(theta_deg))
    omega = m * IMPACT_SPEED * (1 + t["e"]) * arm / (t["I_yy"] + m * arm * arm)
    return omega, omega * arm - t["e"] * IMPACT_SPEED


def method_fig10(spec, run, rows):
    groups = by(rows, "quantity")
    fig, grid = new_figure(4.2, 2)
    theta = [0.5 * k for k in range(181)]
    paper = [eqs_27_28(t) for t in theta]
    facts = {"agrees": [], "differs": []}
    for k, (name, label, plain, unit) in enumerate((
            ("omega_plus", "$\\omega_y^+$ (rad/s)", "omega+", "rad/s"),
            ("v_z_plus", "$V_z^+$ (m/s)", "V_z+", "m/s"))):
        data = sorted(groups.get(name, []), key=lambda r: f(r, "parameter"))
        if not data:
            raise Missing(f"{run.path('cylinder_wall_impact', 'checks.csv')}: no {name} rows")
        ax = fig.add_subplot(grid[0, k])
        ax.plot(theta, [p[k] for p in paper], "-", color=PAPER, lw=1,
                label=f"Eq. {27 + k}, Table 1's cylinder, $V_z^-$ = 1 m/s")
        x = [f(r, "parameter") for r in data]
        ax.fill_between(x, [f(r, "expected") - f(r, "tolerance") for r in data],
                        [f(r, "expected") + f(r, "tolerance") for r in data], color=BAND,
                        label="talus's tolerance about Eq. %d (its mesh)" % (27 + k))
        for verdict, part in sorted(by(data, "verdict").items()):
            ax.plot([f(r, "parameter") for r in part], [f(r, "measured") for r in part],
                    MARK.get(verdict, "+"), mfc="none", color=VERDICT.get(verdict, "C1"),
                    label=f"talus ({verdict})")
        ax.axhline(0, color="0.6", lw=0.5)
        ax.set_xlabel("impact angle $\\theta$ (degrees)")
        ax.set_ylabel(label)
        ax.set_xlim(0, 90)
        ax.legend(loc="lower left")
        facts["agrees"].append(checked_summary(data, plain, " " + unit, "theta"))
        ideal = max(abs(f(r, "expected") - eqs_27_28(f(r, "parameter"))[k]) for r in data)
        facts["agrees"].append(f"talus's Eq. {27 + k} (its 42-vertex mesh's mass, I_yy and "
                               f"corner) within {generate.fmt(ideal)} {unit} of Table 1's "
                               "cylinder's")
        reported = [r for r in data if r["verdict"] == "reported"]
        if reported:
            worst = max(reported, key=error)
            facts["differs"].append(
                f"{plain} outside the checked angles "
                f"(reported): up to {generate.fmt(error(worst))} {unit} off at "
                f"{generate.fmt(f(worst, 'parameter'))} degrees (talus "
                f"{generate.fmt(f(worst, 'measured'))}, Eq. {generate.fmt(f(worst, 'expected'))})")
    finish(fig, spec, run, "Fig. 10 is a picture (no DEM values in the text); its curves are "
           "Eqs. 27-28, drawn with Table 1's D, L, V, rho, I_yy and e. The paper: deviations at "
           "very low and very high angles.")
    return fig, facts


def method_fig12(spec, run, rows):
    curves = by(rows, "quantity", "variant")
    variants = sorted({v for q, v in curves if q == "normal_force"},
                      key=lambda v: float(v.split()[-1]))
    if not variants:
        raise Missing(f"{run.path('mesh_resolution', 'checks.csv')}: no normal_force rows")
    fig, grid = new_figure(5.2, 1)
    inner = grid[0, 0].subgridspec(2, 1, height_ratios=[3, 2], hspace=0.08)
    top = fig.add_subplot(inner[0])
    bottom = fig.add_subplot(inner[1], sharex=top)
    checked = []
    for i, variant in enumerate(variants):
        normal = sorted(curves[("normal_force", variant)], key=lambda r: f(r, "parameter"))
        friction = sorted(curves.get(("tangential_force", variant), []),
                          key=lambda r: f(r, "parameter"))
        lam = variant.split()[-1]
        top.plot([f(r, "parameter") for r in normal], [f(r, "measured") for r in normal], "-",
                 color=f"C{i}", label=f"$\\lambda$ = {lam}")
        top.plot([f(r, "parameter") for r in friction], [f(r, "measured") for r in friction],
                 ":", color=f"C{i}")
        bottom.plot([f(r, "parameter") for r in normal],
                    [f(r, "measured") - f(r, "expected") for r in normal], "-", color=f"C{i}")
        checked += normal
    for ax in (top, bottom):
        ax.axvspan(1, 2, color="0.95", zorder=0)
    within = [r for r in checked if r["verdict"] != "reported"]
    if within:
        tolerance = max(f(r, "tolerance") for r in within)
        kappa = [min(f(r, "parameter") for r in within), max(f(r, "parameter") for r in within)]
        bottom.fill_between(kappa, -tolerance, tolerance, color=BAND, zorder=0,
                            label=f"tolerance where checked ({generate.fmt(tolerance)} of the "
                                  "scale)")
        bottom.legend(loc="upper right")
    top.set_ylabel("force / force scale\n(normal solid, friction dotted)")
    top.legend(ncol=6, loc="center")
    top.tick_params(labelbottom=False)
    bottom.set_ylabel("normal force\nless $\\lambda$ = 16's")
    bottom.set_xlabel("$\\kappa = \\Delta x / L_c$ (shaded: the cube wholly on the wall)")
    summary = checked_summary(checked, "each lambda's normal force against lambda = 16's, "
                              "over the force scale", "", "kappa")
    facts = {"agrees": [summary], "differs": ["the paper gives no force values to compare "
                                              "with (a picture only)"]}
    if within and all(r["verdict"] == "pass" for r in within):
        facts["agrees"].append("so the curves of every lambda overlap, as the paper's do")
    else:
        facts["differs"].insert(0, summary)
        facts["agrees"].remove(summary)
    finish(fig, spec, run, "Fig. 12 is a picture, no values in the text: its curves "
           "\"almost perfectly overlap under different mesh resolutions\" (section 3.2).")
    return fig, facts


def method_fig13(spec, run, rows):
    groups = by(rows, "quantity")
    steps = sorted({q.split("_dt")[1] for q in groups if q.startswith("bed_height_dt")})
    if not steps:
        raise Missing(f"{run.path('dodecahedron_packing', 'checks.csv')}: no bed_height rows")
    beds = sorted(glob.glob(run.path("dodecahedron_packing", "bed_dt*_seed*.png")))
    fig, grid = new_figure(4.2, 2 if beds else 1, width_ratios=[2, 1] if beds else None)
    ax = fig.add_subplot(grid[0, 0])
    facts = {"agrees": [], "differs": []}
    tolerance = 0.0
    for i, dt in enumerate(steps):
        heights = groups[f"bed_height_dt{dt}"]
        ax.plot([f(r, "parameter") + 0.12 * i for r in heights],
                [100 * f(r, "measured") for r in heights], "o", mfc="none", color=f"C{i}",
                label=f"a seed's bed, dt = {dt} s")
        for r in groups.get(f"mean_bed_height_dt{dt}", []):
            tolerance = 100 * f(r, "tolerance")
            ax.axhline(100 * f(r, "measured"), ls="--", color=f"C{i}", lw=1,
                       label=f"mean, dt = {dt} s ({r['verdict']})")
            sentence = (f"dt = {dt} s: mean bed {100 * f(r, 'measured'):.2f} cm over "
                        f"{len(heights)} seeds against about {PAPER_BED_HEIGHT_CM:g} cm "
                        f"(tolerance {tolerance:.1f} cm: {r['verdict']})")
            facts["agrees" if r["verdict"] == "pass" else "differs"].append(sentence)
        low = min(100 * f(r, "measured") for r in heights)
        high = max(100 * f(r, "measured") for r in heights)
        facts["agrees"].append(f"dt = {dt} s: the seeds' beds from {low:.1f} to {high:.1f} cm")
    if tolerance:
        ax.axhspan(PAPER_BED_HEIGHT_CM - tolerance, PAPER_BED_HEIGHT_CM + tolerance,
                   color=BAND, zorder=0, label="talus's tolerance about 16 cm")
    ax.axhline(PAPER_BED_HEIGHT_CM, color=PAPER, lw=1,
               label="paper: about 16 cm (experiment and simulation)")
    ax.set_xlabel("seed of the random fill")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.set_ylabel("bed height (cm)")
    ax.legend(loc="lower right")
    if beds:
        picture = fig.add_subplot(grid[0, 1])
        picture.imshow(plt.imread(beds[0]))
        picture.axis("off")
        match = re.search(r"bed_dt(.+)_seed(\d+)\.png$", beds[0])
        picture.set_title(f"the bed of seed {match.group(2)}, dt {match.group(1)} s "
                          "(Fig. 13 d's counterpart)", fontsize=8)
    facts["differs"].append("the paper's bed pictures (Fig. 13 b, d) are compared by eye "
                            "only; it gives no particle size")
    finish(fig, spec, run, "section 3.3: \"the final packing height in both the experiment and "
           "the simulation was approximately 16 cm\"; Fig. 13 shows pictures.")
    return fig, facts


def method_fig15(spec, run, rows):
    checks = {r["quantity"]: r for r in rows}
    folder = run.path("rotating_drum")
    fields_path = os.path.join(folder, "fields.csv")
    fields = read_csv(fields_path) if os.path.isfile(fields_path) else []
    frames = sorted(glob.glob(os.path.join(folder, "frames", "frame_*.png")))
    fig, grid = new_figure(4.0, 3)
    axes = [fig.add_subplot(grid[0, k]) for k in range(3)]
    facts = {"agrees": [], "differs": []}
    if frames:
        axes[0].imshow(plt.imread(frames[-1]))
        detections_path = os.path.join(folder, "detections.csv")
        detections = read_csv(detections_path) if os.path.isfile(detections_path) else []
        axes[0].plot([float(d["column"]) for d in detections],
                     [float(d["row"]) for d in detections], "+", color="crimson", ms=3,
                     label=f"{len(detections)} found")
        axes[0].legend(loc="upper right")
    else:
        axes[0].text(0.5, 0.5, "no frames/ in the run", ha="center", transform=axes[0].transAxes)
    axes[0].axis("off")
    axes[0].set_title("(a) the last frame, the particles found")

    def value(q):
        return f(checks[q], "measured") if q in checks else float("nan")

    # Cells of fewer than 20 samples are left out, as the case's own figure does.
    used = [r for r in fields if int(r["n_image"]) >= 20 or int(r["n_dem"]) >= 20]
    scale = max([math.hypot(f(r, "u_" + s), f(r, "w_" + s)) for r in used
                 for s in ("image", "dem")] or [1.0])
    cell_size = abs(f(fields[1], "a") - f(fields[0], "a")) if len(fields) > 1 else 0.0
    radius = max((abs(f(r, "a")) for r in fields), default=0.0) + 0.5 * cell_size
    titles = (f"(b) tracked in the pictures: R$^2$ = {value('velocity_r2'):.4f}\n"
              f"against (c) (paper: {PAPER_DRUM_R2} against its experiment)",
              f"(c) the DEM's own velocities: repose {value('repose_angle_dem'):.1f} deg,\n"
              f"lift {value('highest_lift_dem'):.1f} deg (pictures {value('repose_angle'):.1f}, "
              f"{value('highest_lift'):.1f}; paper: none given)")
    for ax, source, name in ((axes[1], "image", titles[0]), (axes[2], "dem", titles[1])):
        ax.set_title(name, fontsize=8)
        if not fields:
            ax.text(0.5, 0.5, "no fields.csv in the run", ha="center", transform=ax.transAxes)
            continue
        part = [r for r in fields if int(r[f"n_{source}"]) >= 20]
        u = [f(r, f"u_{source}") for r in part]
        w = [f(r, f"w_{source}") for r in part]
        ax.quiver([f(r, "a") for r in part], [f(r, "b") for r in part], u, w,
                  [math.hypot(a, b) for a, b in zip(u, w)], cmap="viridis", clim=(0, scale),
                  scale=scale * 12, width=0.005)
        ax.add_patch(plt.Circle((0, 0), radius, fill=False, color="0.4"))
        ax.set_aspect("equal")
        ax.set_xlim(-1.05 * radius, 1.05 * radius)
        ax.set_ylim(-1.05 * radius, 1.05 * radius)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
    for q, what, form in (
            ("velocity_r2", "R^2 of the pictures' velocity field against the DEM's", "{:.4f}"),
            ("detection_recall", "particles found (recall)", "{:.3f}"),
            ("detection_precision", "detections on a particle (precision)", "{:.3f}"),
            ("repose_angle", "angle of repose, pictures against the DEM (deg)", "{:.1f}"),
            ("highest_lift", "highest lift, pictures against the DEM (deg)", "{:.1f}")):
        if q in checks:
            r = checks[q]
            facts["agrees" if r["verdict"] == "pass" else "differs"].append(
                f"{what}: {form.format(f(r, 'measured'))} against "
                f"{form.format(f(r, 'expected'))} ({r['verdict']})")
    if "velocity_r2" in checks:
        facts["agrees"].append(f"R^2 {value('velocity_r2'):.4f}, above the paper's "
                               f"{PAPER_DRUM_R2} (the paper's is simulation against "
                               "experiment, talus's pictures against its own DEM)")
    facts["differs"].append("the paper gives no angle of repose, lift or fill level to compare "
                            "with")
    if not fields or not frames:
        facts["differs"].append("drawn without " + " and ".join(
            n for n, ok in (("fields.csv", fields), ("frames/", frames)) if not ok))
    finish(fig, spec, run, f"section 3.4: velocity fields of simulation and experiment at R^2 = "
           f"{PAPER_DRUM_R2}; \"minor discrepancies\" in the falling layer and the lift, no "
           "numbers.")
    return fig, facts


def blaze_fig13(spec, run, rows):
    fig, grid = new_figure(3.8, 3)
    axes = [fig.add_subplot(grid[0, k]) for k in range(3)]
    facts = {"agrees": [], "differs": []}
    drawn, worst = set(), {}
    for (name, solver), data in sorted(by(rows, "quantity", "variant").items()):
        if "_dt" not in name:
            continue
        data.sort(key=lambda r: f(r, "parameter"))
        quantity, dt = name.split("_dt")
        t = [f(r, "parameter") for r in data]
        ax = axes[0] if quantity == "speed" else axes[1]
        if quantity not in drawn:
            ax.plot(t, [f(r, "expected") for r in data], "-", color=PAPER, lw=1,
                    label="the closed form")
            drawn.add(quantity)
        style = "^" if solver == "reference" else {"1e-3": "o", "1e-4": "+"}.get(dt, "x")
        ax.plot(t, [f(r, "measured") for r in data], style, mfc="none",
                label=f"talus {solver}, dt = {dt} s")
        relative = [error(r) / abs(f(r, "expected")) for r in data if f(r, "expected")]
        axes[2].semilogy([f(r, "parameter") for r in data if f(r, "expected")],
                         [max(x, 1e-17) for x in relative], style + "-", mfc="none", lw=0.6,
                         label=f"{quantity}, {solver}, dt = {dt} s")
        worst[(dt, solver)] = max(relative + [worst.get((dt, solver), 0.0)])
    for (dt, solver), largest in sorted(worst.items()):
        bound = PAPER_FALL_BOUNDS.get(dt)
        if bound:
            facts["agrees" if largest <= bound else "differs"].append(
                f"{solver} solver, dt = {dt} s: speed and drop within a relative "
                f"{generate.fmt(largest)} of the closed forms, the paper's bound {100 * bound:g} %")
    if not drawn:
        raise Missing(f"{run.path('free_fall_drag', 'checks.csv')}: no speed or drop rows")
    for dt, bound in PAPER_FALL_BOUNDS.items():
        axes[2].axhline(bound, color=PAPER, lw=0.8, ls=":")
        axes[2].text(0.02, bound * 1.2, f"paper's bound at dt = {dt} s",
                     transform=axes[2].get_yaxis_transform(), fontsize=7)
    for ax, label in zip(axes, ("speed (m/s)", "drop (m)", "relative error")):
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label)
        ax.legend(loc="lower right" if ax is not axes[2] else "center right")
    finish(fig, spec, run, "section 5.1 (alpha = 0.5): \"the numerical error bound at 0.10% "
           "for a step size of 10^-3 and 0.010% for a step size of 10^-4\"; its curves are a "
           "picture.")
    return fig, facts


def blaze_fig15(spec, run, rows):
    series = by([r for r in rows if r["quantity"] == "kinetic_energy"], "variant")
    if not series:
        raise Missing(f"{run.path('gravity_packing', 'checks.csv')}: no kinetic_energy rows")
    scalars = {(r["quantity"], r["variant"]): r for r in rows if r["quantity"] != "kinetic_energy"}
    fig, grid = new_figure(4.2, 1)
    ax = fig.add_subplot(grid[0, 0])
    facts = {"agrees": [], "differs": []}
    for i, (law, data) in enumerate(sorted(series.items())):
        data.sort(key=lambda r: f(r, "parameter"))

        def scalar(q):
            return f(scalars[(q, law)], "measured") if (q, law) in scalars else float("nan")
        count = scalar("particles")
        octahedra = (f"{count:,.0f} octahedra" if math.isfinite(count)
                     else "octahedra (their count not in checks.csv)")
        ax.semilogy([f(r, "parameter") for r in data], [max(f(r, "measured"), 1e-16)
                    for r in data], "-", color=f"C{i}",
                    label=f"{law} law, {octahedra}" + (
                        f": packing fraction {scalar('packing_fraction'):.3f}"
                        if math.isfinite(scalar("packing_fraction")) else ""))
        end = scalars.get(("kinetic_fraction_end", law))
        if end:
            facts["agrees" if end["verdict"] != "fail" else "differs"].append(
                f"{law} law, {octahedra}: kinetic energy at "
                f"{f(data[-1], 'parameter'):g} s {generate.fmt(f(end, 'measured'))} of its "
                f"peak (below {generate.fmt(f(end, 'tolerance'))}: {end['verdict']})")
        gain = scalars.get(("energy_gain", law))
        if gain:
            facts["agrees" if gain["verdict"] == "pass" else "differs"].append(
                f"{law} law: the energy balance rose by {100 * f(gain, 'measured'):.2g} % of the "
                f"energy released ({gain['verdict']})")
        if math.isfinite(count) and count != PAPER_PACKING_COUNT:
            facts["differs"].append(f"{law} law: {octahedra}, the paper's "
                                    f"{PAPER_PACKING_COUNT:,}")
    ax.axvline(PAPER_PACKING_TIME, color=PAPER, lw=0.8, ls=":")
    ax.text(PAPER_PACKING_TIME, 0.97, " the paper's Fig. 14: 1 s", fontsize=7, va="top",
            transform=ax.get_xaxis_transform())
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy (J)")
    ax.legend(loc="lower left")
    facts["differs"].append("the paper's kinetic energy is a picture with no values (and it "
                            "gives neither size nor material): compared by shape only")
    finish(fig, spec, run, f"section 5.2: {PAPER_PACKING_COUNT:,} polyhedra (128 x 128 x 64), "
           "at rest after 1 s (Fig. 14); Fig. 15 plots their kinetic energy, a picture with no "
           "numbers.")
    return fig, facts


def blaze_fig18_19(spec, run, rows):
    hopper = case_module("hopper_flow")
    checks = {(r["quantity"], r["variant"]): r for r in rows}
    snapshots, series, lacking = {}, {}, []
    for name in hopper.SETS:
        path = run.path("hopper_flow", f"snapshots_{name}.csv")
        if os.path.isfile(path):
            for r in read_csv(path):
                snapshots.setdefault(name, {}).setdefault(float(r["time"]), []).append(r)
        else:
            lacking.append(os.path.basename(path))
        path = run.path("hopper_flow", f"discharge_{name}.csv")
        if os.path.isfile(path):
            series[name] = read_csv(path)
        else:
            lacking.append(os.path.basename(path))
    columns = 4
    fig = plt.figure(figsize=(WIDTH, 8.4))
    grid = fig.add_gridspec(len(snapshots) + 1, columns,
                            height_ratios=[1.3] * len(snapshots) + [1.2])
    for row, name in enumerate(sorted(snapshots, key=hopper.SETS.index)):
        times = sorted(snapshots[name])  # four instants of those written, first and last kept
        if len(times) > columns:
            times = [times[round(k * (len(times) - 1) / (columns - 1))] for k in range(columns)]
        top = max(float(r["z"]) for r in snapshots[name][times[0]]) + 0.03
        for col, t in enumerate(times):
            ax = fig.add_subplot(grid[row, col])
            hopper.draw_snapshot(ax, name, snapshots[name][t], top)
            ax.grid(False)
            ax.set_title(f"{name} (Fig. {PAPER_HOPPER_FIGURE[name]}), t = {t:.2f} s", fontsize=8)
    ax = fig.add_subplot(grid[len(snapshots), :])
    facts = {"agrees": [], "differs": []}
    for i, name in enumerate(series):
        data = series[name]
        n = int(data[0]["bin"]) + int(data[0]["stream"]) + int(data[0]["removed"])
        ax.plot([float(r["time"]) for r in data], [int(r["discharged"]) / n for r in data], "-",
                color=f"C{i}", label=f"{name}: {n:,} particles")
    rates = {}
    for name in hopper.SETS:
        rate = checks.get((f"discharge_rate_{name}", name))
        coefficient = checks.get(("beverloo_coefficient", name))
        if rate:
            rates[name] = f(coefficient, "measured") if coefficient else None
            facts["agrees" if rate["verdict"] == "pass" else "differs"].append(
                f"{name}: {f(rate, 'measured'):.3g} kg/s against Beverloo's "
                f"{f(rate, 'expected'):.3g} kg/s ({rate['verdict']}; Beverloo's correlation, "
                "not the paper's number: it gives none)")
        elif name in series:
            facts["differs"].append(f"{name}: no discharge rate measured in this run (too few "
                                    "through the outlet)")
        for q in ("particles_unaccounted", "particles_astray"):
            r = checks.get((q, name))
            if r and r["verdict"] == "fail":
                facts["differs"].append(f"{name}: {q.replace('_', ' ')} "
                                        f"{generate.fmt(f(r, 'measured'))}")
    if rates.get("marbles") and rates.get("corn"):
        slower = rates["corn"] < rates["marbles"]
        facts["agrees" if slower else "differs"].append(
            f"corn's Beverloo coefficient {rates['corn']:.2f} against the marbles' "
            f"{rates['marbles']:.2f}: the paper's \"flow much slower than spheres\"")
    ax.set_xlabel("time after the outlet opens (s)")
    ax.set_ylabel("share through the outlet")
    ax.set_ylim(0, 1)
    ax.legend(loc="lower right")
    if lacking:
        facts["differs"].append("drawn without " + ", ".join(lacking))
    facts["differs"].append("the paper's Figs. 18-19 are pictures, compared by eye: no "
                            "dimensions, sizes or rates are given")
    finish(fig, spec, run, "section 5.3: 836 marbles (Fig. 18) and 13,824 corn-shaped "
           "polyhedra (Fig. 19) through a square hopper, 5 s; pictures only, no numbers.")
    return fig, facts


# ---- The scaling study (method paper Figs. 17-18) ------------------------------------------
SCALING_WHAT = "experiments/scaling/run_scaling.py's scaling.json"


def count_words(n):
    """A particle count as the index and legend write it: 1e6, 1.5e6, 2e5; below 1000 whole."""
    if n < 1000:
        return generate.fmt(n)
    exponent = int(math.floor(math.log10(n)))
    mantissa = float(f"{n / 10 ** exponent:.3g}")
    if mantissa >= 10:  # 9.999e5 rounds to 10e5
        mantissa, exponent = mantissa / 10, exponent + 1
    return f"{mantissa:g}e{exponent}"


def and_list(words):
    """'a', 'a and b', 'a, b and c'."""
    return ", ".join(words[:-1]) + " and " + words[-1] if len(words) > 1 else "".join(words)


def percent(efficiency):
    return f"{100 * efficiency:.1f} %"


class ScalingRun:
    """One --scaling file: the machine, commit, backend and command it records, and its rows
    that can be drawn (timed after the setup, no more ranks than GPUs) with those left out."""

    def __init__(self, order, path, data):
        self.id, self.order, self.dir = f"R{order}", order, path
        self.commit, self.backend = str(data["commit"]), str(data["backend"])
        self.version = "scaling study"
        self.command = str(data["driver_command"])
        m = data["machine"]
        names, self.gpus = m.get("gpu_names"), m.get("gpus")
        names = names if isinstance(names, list) and names else []
        if names and all(n == names[0] for n in names):
            gpu_words = f"{len(names)} × {names[0]}"
            model = names[0].split(",")[0].strip()
            self.short = f"{len(names)}×{model[7:] if model.startswith('NVIDIA ') else model}"
        else:
            gpu_words = "; ".join(names) or "GPUs not recorded"
            self.short = f"{len(names)} GPUs" if names else "GPUs not recorded"
        cores = m.get("usable_cpus")
        self.machine = gpu_words + "".join(
            f", {x}" for x in (m.get("cpu_model"), f"{cores} cores" if cores else None) if x)
        self.used, self.rows, self.left_out = [], [], []
        untimed = [r for r in data["runs"] if "timed_steps" not in r]
        timed = [r for r in data["runs"] if "timed_steps" in r]
        known = generate.is_number(self.gpus) and self.gpus > 0
        shared = [r for r in timed if known and r["ranks"] > self.gpus]
        self.rows = [r for r in timed if not (known and r["ranks"] > self.gpus)]
        if untimed:
            self.left_out.append(f"{len(untimed)} of its rows timed with the run's setup (no "
                                 "timed_steps: from before talus's steady summary)")
        if shared:
            self.left_out.append(f"{len(shared)} of its rows on more ranks than its {self.gpus} "
                                 "GPUs (ranks sharing a GPU)")

    def footer(self):
        return (f"talus: commit {self.commit} on the {self.backend} backend, {self.short} "
                f"(run {self.id}: {self.dir})")


def read_scaling(path, order):
    """A --scaling file as a ScalingRun; a Refusal naming the file when it is missing, not JSON
    or not as run_scaling.py writes it on the CUDA backend."""
    data = generate.load_json(path)
    generate.require(data, ("machine", "commit", "backend", "driver_command", "runs"), path,
                     "the top level", SCALING_WHAT, lists=("runs",))
    generate.require(data["machine"], (), path, "'machine'", SCALING_WHAT)
    if data["backend"] != "cuda":
        raise generate.Refusal(f"{path}: its backend is {data['backend']!r}, not 'cuda': its "
                               "ranks are not GPUs")
    for i, row in enumerate(data["runs"]):
        generate.require(row, ("mode", "ranks", "particles", "efficiency"), path, f"runs[{i}]",
                         SCALING_WHAT)
        if row["mode"] not in ("strong", "weak"):
            raise generate.Refusal(f"{path}: runs[{i}]'s 'mode' is {row['mode']!r}, not "
                                   "'strong' or 'weak'")
        for key in ("ranks", "particles", "efficiency"):
            value = row[key]
            if not generate.is_number(value) or not math.isfinite(value) or value <= 0 or (
                    key == "ranks" and value != int(value)):
                raise generate.Refusal(f"{path}: runs[{i}]'s '{key}' is {value!r}, not a "
                                       + ("whole number" if key == "ranks" else "number")
                                       + " above 0; expected " + SCALING_WHAT)
    return ScalingRun(order, path, data)


def scaling_series(runs):
    """{(run, mode, count): rows by rank count}: count is the particles a GPU (weak) or in all
    (strong), the series in the order of the files and of their rows."""
    series = {}
    for run in runs:
        for r in run.rows:
            count = r["particles"] / r["ranks"] if r["mode"] == "weak" else r["particles"]
            series.setdefault((run, r["mode"], count), []).append(r)
    for rows in series.values():
        rows.sort(key=lambda r: r["ranks"])
    return series


def series_words(mode, count):
    return f"{count_words(count)} a GPU" if mode == "weak" else f"{count_words(count)} in all"


def method_fig17_18(spec, runs):
    """Two panels, (a) strong and (b) weak scaling: each series' efficiency against the GPUs,
    the paper's statements as a line over 1-16 GPUs (strong) and a point at 16 (weak)."""
    series = scaling_series(runs)
    if not series:
        raise Missing("no scaling file has a row to draw (" + "; ".join(
            f"{r.dir}: " + (", ".join(r.left_out) or "no runs") for r in runs) + ")")
    top = max([PAPER_GPUS] + [r["ranks"] for rows in series.values() for r in rows])
    ticks = [2 ** k for k in range(int(math.log2(top)) + 1)]
    efficiencies = [100 * r["efficiency"] for rows in series.values() for r in rows]
    low = min(efficiencies + [100 * PAPER_EFFICIENCY])
    bottom, ceiling = max(0, 10 * math.floor(low / 10 - 1)), max(110, max(efficiencies) + 10)
    fig, grid = new_figure(4.2, 2)
    paper_note = "the paper's text, not data"
    for k, (mode, name) in enumerate((("strong", "(a) strong scaling (Fig. 17)"),
                                      ("weak", "(b) weak scaling (Fig. 18)"))):
        ax = fig.add_subplot(grid[0, k])
        ax.axhline(100, color="0.6", lw=0.8, ls="--", label="ideal (100 %)")
        if mode == "strong":
            ax.fill_between([1, PAPER_GPUS], 100 * PAPER_EFFICIENCY, ceiling, color="0.94",
                            zorder=0)
            ax.plot([1, PAPER_GPUS], [100 * PAPER_EFFICIENCY] * 2, "-", color=PAPER, lw=1.2,
                    label=f"{paper_note}: \"remains above 85% up to 16 GPUs\"")
        else:
            ax.plot([PAPER_GPUS], [100 * PAPER_EFFICIENCY], "s", color=PAPER, ms=6, mfc="none",
                    mew=1.2, label=f"{paper_note}: with 5.0e6 particles a GPU,\n"
                                   "\"to approximately 85% at 16 GPUs\"")
        drawn = 0
        for i, ((run, m, count), rows) in enumerate(series.items()):
            if m != mode:
                continue
            n = [r["ranks"] for r in rows]
            e = [100 * r["efficiency"] for r in rows]
            ax.plot(n, e, "o-", color=f"C{i}",
                    label=f"{mode}, {series_words(mode, count)}, {run.short} ({run.id})")
            for x, y in zip(n, e):
                if x > 1:
                    ax.annotate(f"{y:.1f} %", (x, y), xytext=(5, -3),
                                textcoords="offset points", fontsize=7, color=f"C{i}")
            drawn += 1
        if not drawn:
            ax.text(0.5, 0.5, f"no {mode} rows in the scaling files", ha="center",
                    transform=ax.transAxes)
        ax.set_xscale("log", base=2)
        ax.set_xticks(ticks)
        ax.set_xticklabels([str(t) for t in ticks])
        ax.set_xlim(0.8, top * 1.25)
        ax.set_ylim(bottom, ceiling)
        ax.set_xlabel("GPUs (talus: MPI ranks, a GPU each)")
        ax.set_ylabel("parallel efficiency (%)")
        ax.set_title(name, fontsize=9)
        ax.legend(loc="lower left")
    facts = {"agrees": [], "differs": []}
    compare = (f"the paper's {100 * PAPER_EFFICIENCY:g} % (strong: above it up to "
               f"{PAPER_GPUS} GPUs; weak: about it at {PAPER_GPUS} GPUs with "
               f"{count_words(PAPER_WEAK_PER_GPU)} a GPU)")
    for run in runs:
        for gpus in sorted({r["ranks"] for r in run.rows if r["ranks"] > 1}):
            above, below = [], []
            for (owner, mode, count), rows in series.items():
                for r in rows:
                    if owner is run and r["ranks"] == gpus:
                        words = (f"{mode} {percent(r['efficiency'])} "
                                 + (f"at {count_words(count)} a GPU" if mode == "weak"
                                    else f"for {count_words(count)}"))
                        (above if r["efficiency"] >= PAPER_EFFICIENCY else below).append(words)
            where = f"{gpus} GPUs ({run.short}, {run.id})"
            if above:
                facts["agrees"].append(f"{where}: {', '.join(above)}: at or above {compare}")
            if below:
                facts["differs"].append(f"{where}: {', '.join(below)}: below {compare}")
        facts["differs"] += [f"{run.id}: {words}, left out" for words in run.left_out]
    most = max(r["ranks"] for rows in series.values() for r in rows)
    if most < PAPER_GPUS:
        facts["differs"].append(f"measured on up to {most} GPU{'s' if most > 1 else ''}; the "
                                f"paper's statements reach {PAPER_GPUS}")
    weak = sorted({c for (_, m, c) in series if m == "weak"})
    if weak and PAPER_WEAK_PER_GPU not in weak:
        facts["differs"].append(f"weak at {', '.join(count_words(c) for c in weak)} a GPU, the "
                                f"paper's Fig. 18 (b) at {count_words(PAPER_WEAK_PER_GPU)}")
    finish(fig, spec, runs, PAPER_SCALING_TEXT + "; no table: drawn as statements.")
    return fig, facts


def scaling_state(runs):
    """The 'To come' row's state while the figure is drawn: what it holds, what is still to run."""
    series = scaling_series(runs)
    most = max(r["ranks"] for rows in series.values() for r in rows)
    weak = {c for (_, m, c) in series if m == "weak"}
    strong = {c for (_, m, c) in series if m == "strong"}
    still = ([f"more than {most} GPUs (the paper: up to {PAPER_GPUS})"] if most < PAPER_GPUS
             else [])
    lacking = [count_words(c) for c in PAPER_WEAK_COUNTS if c not in weak]
    if lacking:
        still.append(f"weak at {and_list(lacking)} a GPU")
    lacking = [count_words(c) for c in PAPER_STRONG_TOTALS if c not in strong]
    if lacking:
        still.append(f"the paper's {and_list(lacking)} strong total")
    held = ", ".join(f"{m} {series_words(m, c)}" for (_, m, c) in series)
    return (f"partly drawn ({', '.join(r.id for r in runs if r.rows)}: {held}, up to {most} "
            f"GPU{'s' if most > 1 else ''}); "
            + (f"to come (multi-GPU): {'; '.join(still)}" if still else "nothing to come"))


METHOD, BLAZE = "Method paper", "BLAZE-DEM"


def figure(paper, number, title, case, draw):
    """A figure redrawn: its PNG is named after the paper, the figure's number and the case
    (method_fig10_cylinder_wall_impact.png)."""
    stem = ("method" if paper == METHOD else "blaze") + "_fig" + "_".join(
        re.findall(r"\d+", number))
    return {"file": f"{stem}_{case}.png", "paper": paper, "number": number, "title": title,
            "case": case, "draw": draw}


FIGURES = [
    figure(METHOD, "Fig. 10", "cylinder-wall impact, omega+ and V_z+ against theta "
           "(Eqs. 27-28)", "cylinder_wall_impact", method_fig10),
    figure(METHOD, "Fig. 12", "wall mesh resolution, the force against kappa for each lambda",
           "mesh_resolution", method_fig12),
    figure(METHOD, "Fig. 13", "63 dodecahedra packed in a 10 cm cylinder, the bed heights",
           "dodecahedron_packing", method_fig13),
    figure(METHOD, "Fig. 15", "quasi-2D rotating drum, velocity fields, angle of repose and "
           "lift", "rotating_drum", method_fig15),
    figure(BLAZE, "Fig. 13", "free fall with quadratic drag against the closed forms",
           "free_fall_drag", blaze_fig13),
    figure(BLAZE, "Fig. 15", "gravity packing of octahedra, the kinetic energy against time",
           "gravity_packing", blaze_fig15),
    figure(BLAZE, "Figs. 18-19", "hopper discharge of marbles and corn-shaped polyhedra, "
           "coloured by layer", "hopper_flow", blaze_fig18_19),
]
# Drawn from --scaling files, not from a case of talus validate.
SCALING = dict(figure(METHOD, "Figs. 17-18", "strong and weak scaling over GPUs, the parallel "
                      "efficiency", "scaling", method_fig17_18), source="scaling.json")
# The papers' figures of the kind above that are not redrawn yet, with what they need.
TO_COME = [
    (METHOD, "Figs. 17-18", "strong and weak scaling over GPUs",
     "to come (multi-GPU): talus runs on one GPU so far", PAPER_SCALING_TEXT),
    (BLAZE, "Fig. 16", "the time against the number of polyhedra on one GPU (performance, "
     "not validation)",
     "to come: a timing over particle counts, which talus validate does not write; it belongs "
     "to the benchmarks' report (reports/generate.py)",
     "\"the computational time scales by a factor N up to a million particles\"; the TESLA K20 "
     "\"is only 30% faster\" than the GTX 780M (section 5.2)"),
]


# ---- The index ----------------------------------------------------------------------------
def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def index(runs, drawn, missing, problems, command, to_come=TO_COME):
    out = ["# reports/figures", "",
           "The two papers' figures redrawn in one style from the results of `talus validate`, "
           "each beside the numbers the paper gives for it (the papers' figures are pictures: "
           "only the numbers of their text and tables are drawn as the paper's). Written by "
           "`reports/figures/redraw.py` (`reports/README.md`, \"reports/figures\"); do not edit "
           "by hand. Made by:", "", "```sh", command, "```", "", "## Runs", "",
           "| run | directory | machine | commit | backend | version | command | figures |",
           "|---|---|---|---|---|---|---|---|"]
    for run in runs:
        out.append("| " + " | ".join(cell(x) for x in (
            run.id, f"`{run.dir}`", run.machine, f"`{run.commit}`", run.backend, run.version,
            f"`{run.command}`" if run.command != "not recorded" else run.command,
            ", ".join(run.used) or "none")) + " |")
    if not runs:
        out.append("| — | no results directory could be read | | | | | | |")
    out += ["", "## Figures", "", "| figure | the paper's | from | agrees | does not |",
            "|---|---|---|---|---|"]
    for spec, run, facts in drawn:
        out.append("| " + " | ".join(cell(x) for x in (
            f"[`{spec['file']}`]({spec['file']})",
            f"{spec['paper']} {spec['number']}: {spec['title']}",
            f"{run.id} (`{spec.get('source', spec['case'])}`)",
            "; ".join(facts["agrees"]) or "—",
            "; ".join(facts["differs"]) or "—")) + " |")
    out += ["", "## Missing", ""]
    if missing:
        out += ["| figure | the paper's | why |", "|---|---|---|"]
        out += ["| " + " | ".join(cell(x) for x in (
            f"`{spec['file']}`", f"{spec['paper']} {spec['number']}", why)) + " |"
            for spec, why in missing]
    else:
        out.append("None: every figure above was drawn.")
    if problems:
        heading = ("Results directories not read:" if all(
            not isinstance(r, ScalingRun) for r in runs) else "Inputs not read or not drawn:")
        out += ["", heading, ""] + [f"- {cell(p)}" for p in problems]
    out += ["", "## To come", "", "| the paper's | what | state | the paper's numbers |",
            "|---|---|---|---|"]
    out += ["| " + " | ".join(cell(x) for x in (f"{paper} {number}", what, state, numbers))
            + " |" for paper, number, what, state, numbers in to_come]
    return "\n".join(out) + "\n"


def small_png(fig):
    """The figure as a PNG of 256 colours (a third of the size of matplotlib's own)."""
    drawn, small = io.BytesIO(), io.BytesIO()
    fig.savefig(drawn, format="png")
    plt.close(fig)
    drawn.seek(0)
    Image.open(drawn).convert("RGB").quantize(colors=256).save(small, format="png",
                                                               optimize=True)
    return small.getvalue()


def draw_scaling(runs, output, drawn, missing, problems):
    """Figs. 17-18 from the --scaling files into `output`, its entry put after the method
    paper's other figures in `drawn` (or `missing`); a file without a row to draw is one of
    `problems`. Returns the 'To come' rows to write: the one of Figs. 17-18 says what is still
    to run where the figure is drawn."""
    for run in runs:
        if not run.rows:
            problems.append(f"{run.dir}: no row to draw (" + (", ".join(run.left_out)
                                                              or "its runs are empty") + ")")
    target = os.path.join(output, SCALING["file"])
    place = sum(spec["paper"] == METHOD for spec, *_ in drawn)
    try:
        fig, facts = method_fig17_18(SCALING, runs)
    except Missing as e:
        plt.close("all")
        missing.insert(sum(spec["paper"] == METHOD for spec, _ in missing), (SCALING, str(e)))
        if os.path.exists(target):  # an earlier run's figure must not stand for this one
            os.unlink(target)
        return TO_COME
    generate.write_atomic(target, small_png(fig))
    used = [r for r in runs if r.rows]
    for run in used:
        run.used.append(f"{SCALING['paper']} {SCALING['number']}")
    drawn.insert(place, (SCALING, argparse.Namespace(id=", ".join(r.id for r in used)), facts))
    to_come = [row if row[1] != SCALING["number"] else row[:3] + (scaling_state(used), row[4])
               for row in TO_COME]
    return to_come


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", nargs="*", metavar="RESULTS_DIR",
                        help="an output directory of talus validate")
    parser.add_argument("--output", default=HERE, metavar="DIR",
                        help="where the figures and README.md go (default reports/figures/)")
    parser.add_argument("--provenance", metavar="FILE",
                        help="JSON: results directory (as given, or its last part) -> "
                             "{machine, command}, for what validation-results.json does not "
                             "record")
    parser.add_argument("--scaling", nargs="+", action="extend", default=[], metavar="FILE",
                        help="a scaling.json of experiments/scaling/run_scaling.py (CUDA "
                             "backend): draws the method paper's Figs. 17-18; give it after "
                             "the directories")
    args = parser.parse_args(argv[1:])
    if not args.results:
        parser.error("the following arguments are required: RESULTS_DIR (with --scaling, give "
                     "the directories first, or end --scaling's files with --)")
    try:
        provenance = generate.read_provenance(args.provenance)
        scaling = [read_scaling(path, len(args.results) + k)
                   for k, path in enumerate(args.scaling, 1)]
    except generate.Refusal as e:
        print(f"redraw.py: {e}", file=sys.stderr)
        return 2
    plt.rcParams.update(STYLE)
    os.makedirs(args.output, exist_ok=True)
    runs, problems = read_runs(args.results, provenance)
    drawn, missing = [], []
    for spec in FIGURES:
        target = os.path.join(args.output, spec["file"])
        try:
            run, rows = case_rows(runs, spec["case"])
            fig, facts = spec["draw"](spec, run, rows)
        except (Missing, KeyError, ValueError, IndexError) as e:
            plt.close("all")
            why = str(e) if isinstance(e, Missing) else (
                f"{run.path(spec['case'])}: its files are not as talus validate writes them "
                f"({type(e).__name__}: {e})")
            missing.append((spec, why))
            if os.path.exists(target):  # an earlier run's figure must not stand for this one
                os.unlink(target)
            continue
        generate.write_atomic(target, small_png(fig))
        run.used.append(f"{spec['paper']} {spec['number']}")
        drawn.append((spec, run, facts))
    to_come = TO_COME
    if scaling:
        to_come = draw_scaling(scaling, args.output, drawn, missing, problems)
    command = " ".join(["/usr/bin/python3 reports/figures/redraw.py"]
                       + [shlex.quote(a) for a in argv[1:]])
    generate.write_atomic(os.path.join(args.output, "README.md"), index(
        runs + scaling, drawn, missing, problems, command, to_come).encode("utf-8"))
    for line in problems + [f"{s['paper']} {s['number']} ({s['file']}) not drawn: {why}"
                            for s, why in missing]:
        print(f"redraw.py: {line}", file=sys.stderr)
    print(f"redraw.py: {len(drawn)} of {len(FIGURES) + bool(scaling)} figures drawn into "
          f"{args.output}", file=sys.stderr)
    return 0 if not problems and not missing else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
