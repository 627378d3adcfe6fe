#!/usr/bin/python3
"""How the fixed bed's porosity depends on the contact stiffness, and what stiffness costs.

The pellets fall up to 1.5 m and land at about 6 m/s. DEM softens the stiffness to afford the
step (the volume law's critical step grows as 1/sqrt(E)), but a soft pellet landing that fast
sinks deep into the pellets it hits: a face-on landing at E = 1e6 Pa overlaps about 0.6 mm (11 %
of a pellet), an edge or a corner more, and the bed packs denser than stiff pellets would. This
study feeds the same small bed (150 pellets into the full 1.80 m tube, so every pellet falls as
far as the first pellets of the full bed) at several Young's moduli and seeds with fixed_bed.py
and tabulates the porosity, the overlaps (the volume check), the bed height and the cost.

    /usr/bin/python3 experiments/fixed_bed/stiffness_study.py --talus build/talus \\
        --output scratch/stiffness [--moduli 1e6 1e7 1e8] [--seeds 1 2] [--pellets 150] \\
        [--backend cpu] [--threads 2]

Each (E, seed) runs into OUTPUT/E<E>-s<seed>/ (fixed_bed.py's folder; one that has bed.json is
reused), then OUTPUT/stiffness.json, stiffness.md and stiffness.png (porosity against E with
each seed, and the radial profiles) are written; --collect runs nothing and tabulates the cases
that have ended. Needs numpy and matplotlib.
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "beds"))
from fixed_bed import pellet_spec  # noqa: E402
from sittings import write_atomically  # noqa: E402


def case_name(modulus, seed):
    """E1e7-s2: the case's folder."""
    return "E" + f"{modulus:.0e}".replace("e+0", "e").replace("e+", "e") + f"-s{seed}"


def run_case(a, modulus, seed):
    folder = os.path.join(a.output, case_name(modulus, seed))
    if not os.path.exists(os.path.join(folder, "bed.json")):
        argv = [sys.executable, os.path.join(HERE, "fixed_bed.py"), "--talus", a.talus,
                "--backend", a.backend, "--pellets", str(a.pellets), "--seed", str(seed),
                "--youngs-modulus", repr(modulus), "--points", str(a.points), "--output", folder]
        if a.threads:
            argv += ["--threads", str(a.threads)]
        print("stiffness_study.py: " + " ".join(argv), flush=True)
        proc = subprocess.run(argv, capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"stiffness_study.py: {' '.join(argv)} failed ({proc.returncode}):\n"
                     + proc.stderr[-3000:])
    bed = json.load(open(os.path.join(folder, "bed.json")))
    r = bed["result"]
    return {"youngs_modulus_pa": modulus, "seed": seed, "folder": folder,
            "time_step_s": bed["time_step_s"], "steps": bed.get("steps"),
            "run_wall_seconds": bed["run_wall_seconds"], "pellets": r["pellets"],
            "surface_m": r["surface_m"], "porosity": r.get("porosity"),
            "porosity_error": r.get("porosity_error"), "core_z_m": r.get("core_z_m"),
            "volume_check": r["volume_check"], "radial_profile": r.get("radial_profile"),
            "commit": bed["commit"], "machine": bed["machine"], "command": bed["command"]}


def markdown(study):
    lines = ["# Fixed bed: porosity against contact stiffness", "",
             f"{study['pellets']} pellets (`{pellet_spec(16)}`) fed into the full 1.80 m "
             "tube, so each falls as far as the full bed's first pellets; step 0.2 of the "
             f"critical one. talus `{study['commit']}`, {study['machine']}. Command:", "",
             "    " + study["command"], "",
             "| E, Pa | seed | time step, s | steps | run, s | bed height, m | porosity | ± | "
             "found / summed volume |", "|---|---|---|---|---|---|---|---|---|"]
    for c in study["cases"]:
        v = c["volume_check"]
        lines.append(f"| {c['youngs_modulus_pa']:.0e} | {c['seed']} | {c['time_step_s']:.3g} | "
                     f"{c['steps'] or ''} | {c['run_wall_seconds']:.0f} | {c['surface_m']:.4f} | "
                     f"{c['porosity']:.4f} | {c['porosity_error']:.4f} | "
                     f"{v['found_over_summed']:.4f} ± {v['error']:.4f} |")
    lines += ["", "| E, Pa | mean porosity over the seeds | their spread (max − min) |",
              "|---|---|---|"]
    for e, m in study["by_modulus"].items():
        lines.append(f"| {float(e):.0e} | {m['porosity']:.4f} | {m['spread']:.4f} |")
    return "\n".join(lines) + "\n"


def figure(study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    ax = axes[0]
    for c in study["cases"]:
        ax.errorbar(c["youngs_modulus_pa"], c["porosity"], yerr=c["porosity_error"], fmt="o",
                    color=f"C{c['seed'] - 1}", label=f"seed {c['seed']}")
    es = sorted(float(e) for e in study["by_modulus"])
    ax.plot(es, [study["by_modulus"][f"{e:g}"]["porosity"] for e in es], "k-", lw=1,
            label="mean over the seeds")
    handles, labels = ax.get_legend_handles_labels()
    keep = {l: h for h, l in zip(handles, labels)}
    ax.legend(keep.values(), keep.keys())
    ax.set_xscale("log")
    ax.set_xlabel("Young's modulus of pellets and tube, Pa")
    ax.set_ylabel("porosity of the bed's core")
    ax.set_title("(a) porosity against stiffness")
    ax = axes[1]
    for c in study["cases"]:
        prof = c["radial_profile"] or []
        ax.plot([p["from_wall_d"] for p in prof], [p["porosity"] for p in prof], marker="o", ms=2,
                color=f"C{es.index(c['youngs_modulus_pa']) + 2}",
                ls="-" if c["seed"] == 1 else "--",
                label=f"E {c['youngs_modulus_pa']:.0e}, seed {c['seed']}")
    ax.legend(fontsize=7)
    ax.set_xlabel("distance from the wall (pellet diameters)")
    ax.set_ylabel("porosity of the ring")
    ax.set_title("(b) radial profiles")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--talus", default=os.path.join(os.path.dirname(os.path.dirname(HERE)),
                                                   "build", "talus"))
    p.add_argument("--output", required=True)
    p.add_argument("--moduli", type=float, nargs="+", default=[1e6, 1e7, 1e8])
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    p.add_argument("--pellets", type=int, default=150)
    p.add_argument("--points", type=int, default=100000)
    p.add_argument("--backend", choices=("auto", "cpu", "cuda"), default="cpu")
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--collect", action="store_true",
                   help="run nothing: tabulate the cases of OUTPUT that have ended (bed.json)")
    a = p.parse_args(argv)
    if a.pellets < 50:
        p.error("--pellets must be at least 50: a bed shallower has no core to measure")
    os.makedirs(a.output, exist_ok=True)
    wanted = [(e, s) for e in a.moduli for s in a.seeds]
    if a.collect:
        wanted = [(e, s) for e, s in wanted
                  if os.path.exists(os.path.join(a.output, case_name(e, s), "bed.json"))]
        if not wanted:
            sys.exit(f"stiffness_study.py: no case in {a.output} has ended")
    cases = [run_case(a, e, s) for e, s in wanted]
    by_modulus = {}
    for e in sorted({c["youngs_modulus_pa"] for c in cases}):
        ps = [c["porosity"] for c in cases if c["youngs_modulus_pa"] == e]
        by_modulus[f"{e:g}"] = {"porosity": float(np.mean(ps)),
                                "spread": float(max(ps) - min(ps))}
    study = {"pellets": a.pellets, "cases": cases, "by_modulus": by_modulus,
             "commit": cases[0]["commit"], "machine": cases[0]["machine"],
             "command": " ".join([sys.executable] + (argv if argv is not None else sys.argv))}
    write_atomically(os.path.join(a.output, "stiffness.json"), json.dumps(study, indent=1) + "\n")
    write_atomically(os.path.join(a.output, "stiffness.md"), markdown(study))
    figure(study, os.path.join(a.output, "stiffness.png"))
    print(markdown(study))
    return 0


if __name__ == "__main__":
    sys.exit(main())
