#!/usr/bin/env python3
"""Writes the poured-bed scenes: one YAML per (shape, contact law) into an output directory.

Each scene drops a lattice of randomly oriented particles (10 mm circumscribed diameter, the
issue's material: density 1200, E = 5 MPa, nu = 0.3, mu = 0.4, eps = 0.5) into an open box and
lets it settle under gravity. Python 3 standard library only, so that it runs on any machine.

    make_scenes.py OUT_DIR [--particles 8640] [--end 1.0] [--dt 1e-5] [--talus BIN] [--auto]

Case names are <shape>_<law>[_<tag>]; `cases.txt` in OUT_DIR lists them, one a line: case,
shape, law, time step and, when --talus is given, the critical step talus estimates for it.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

# The shapes, all of 10 mm circumscribed diameter. The cylinder is the paper's 20-gon
# prism (paper section 3.1: D = 8 mm, L = 5.3 mm, 80 triangles) scaled to the same 10 mm
# circumscribed diameter, sqrt(D^2 + L^2), with its aspect ratio L / D = 0.6625 kept.
SHAPES = {
    "tetrahedron": "tetrahedron:0.01",
    "cube": "cube:0.01",
    "octahedron": "octahedron:0.01",
    "dodecahedron": "dodecahedron:0.01",
    "icosahedron": "icosahedron:0.01",
    "cylinder": "cylinder:0.00834,0.00552,20",
    "mineral": "mineral:0.01",
}
# The default law for every shape; the paper's law as printed only for the shapes whose poured
# beds it cannot settle (docs/contact.md, "Why the paper's law cannot rest"): the "before".
PAPER_LAW_SHAPES = ("cube", "tetrahedron")

CIRCUMSCRIBED_DIAMETER = 0.01  # m; the lattice spacing and box are sized from it
MATERIAL = {"density": 1200, "youngs_modulus": 5.0e6, "poisson_ratio": 0.3, "friction": 0.4,
            "restitution": 0.5}


def lattice_layout(particles, columns):
    """The lattice as columns x columns x layers holding at least `particles`.

    A narrow, tall lattice on purpose: the bed must be several diameters deeper than the 2 + 3
    diameters the core leaves out at its floor and free surface, even for the tetrahedron, whose
    volume is only 0.064 d^3. Ten columns make a box of 10.5 d, the core 4.5 d wide.
    """
    if columns is None:
        columns = max(3, min(10, round(particles ** (1.0 / 3.0))))
    layers = max(1, math.ceil(particles / (columns * columns)))
    return columns, layers


def scene_text(case, spec, law, dt_text, steps, args, columns, layers, dt_note=""):
    """The scene YAML. `dt_text` is a number or 'auto'; `steps` the run's steps (None: unknown)."""
    d = CIRCUMSCRIBED_DIAMETER
    # 5% above the bounding diameter: no two bounding spheres touch at the start, whatever the
    # random orientations (the loader requires at least the diameter).
    spacing = 1.05 * d
    width = columns * spacing
    top = layers * spacing
    # The region a hair larger than columns x layers spacings, so floor(size / spacing) cannot
    # round down to one lattice point fewer.
    slack = 1e-9
    dt_for_probes = float(dt_text) if steps else args.auto_guess
    probe_every = max(1, round(args.probe_interval / dt_for_probes))
    # Trajectory frames at step 0 (always written) and at the last step (written whatever
    # `every` is); `every` above the step count asks for nothing in between.
    frame_every = (steps + 1) if steps else (1 << 40)
    m, nu = MATERIAL, MATERIAL["poisson_ratio"]
    region_max = f"[{width * (1 + slack)!r}, {width * (1 + slack)!r}, {top * (1 + slack)!r}]"
    box_max = f"[{width!r}, {width!r}, {top + spacing!r}]"
    count = layers * columns * columns
    return f"""\
# {case}: {count} particles ({spec}) poured from a {columns} x {columns} x {layers} lattice
# with random orientations into an open box, settled under gravity.
# Written by experiments/beds/make_scenes.py; contact law {law}, time step {dt_text} s{dt_note}.
time: {{step: {dt_text}, end: {args.end}}}
seed: {args.seed}

materials:
  grain: {{density: {m['density']}, youngs_modulus: {m['youngs_modulus']}, poisson_ratio: {nu},
          friction: {m['friction']}, restitution: {m['restitution']}}}

templates:
  grain: {{shape: "{spec}", material: grain}}

particles:
  - lattice:
      template: grain
      region: {{box: {{min: [0, 0, 0], max: {region_max}}}}}
      spacing: {spacing!r}
      random_orientation: true
      seed: {args.seed}

walls:
  - box: {{name: box, min: [0, 0, 0], max: {box_max}, open_top: true, material: grain}}

effects:
  gravity: [0, 0, -9.81]
  contact: {law}
  friction: true
  rotation: true

outputs:
  trajectories: {{every: {frame_every}, directory: frames}}
  probes: {{every: {probe_every}, file: probes.csv,
           quantities: [kinetic_energy, energy, contact_count, bed_height]}}
"""


def ask_talus(talus, spec, law, dt_text, run_end, args):
    """The summary of a run of a tiny copy of the scene (8 particles, on the host) to run_end.

    The time-step advisor depends on the templates, materials, law, walls and gravity, not on how
    many particles there are (two of a template suffice), so the tiny copy answers for the bed.
    """
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "advice.yaml")
        with open(path, "w") as f:
            f.write(scene_text("advice", spec, law, dt_text, None, args, 2, 2))
        out = subprocess.run([talus, "run", path, "--backend", "cpu", "--threads", "1", "--quiet",
                              "--allow-unstable-step", "--end", repr(run_end), "--output", tmp],
                             capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"make_scenes.py: {talus} could not give the time-step advice for {spec} "
                     f"({law}):\n{out.stderr}")
        return json.loads(out.stdout)


def critical_step(talus, spec, law, args):
    """The advisor's dt_crit (one step at --dt, whatever its stability)."""
    return ask_talus(talus, spec, law, repr(args.dt), args.dt, args)["critical_time_step"]


def advised_step(talus, spec, law, crit, args):
    """What `step: auto` takes (0.2 dt_crit), as talus computes it: a few steps of it."""
    return ask_talus(talus, spec, law, "auto", crit, args)["time_step"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="directory for the scene files (created)")
    parser.add_argument("--particles", type=int, default=8640,
                        help="at least this many particles (rounded up to full lattice layers)")
    parser.add_argument("--columns", type=int, default=None,
                        help="lattice columns per side (default: 10, fewer for small beds)")
    parser.add_argument("--end", type=float, default=1.0, help="end time, s")
    parser.add_argument("--dt", type=float, default=1e-5, help="time step, s")
    parser.add_argument("--auto", action="store_true",
                        help="the default law at the advised step (step: auto, 0.2 dt_crit) "
                             "instead of --dt; the paper's law is left out (its auto step is "
                             "about 2e-11 s)")
    parser.add_argument("--talus", help="the talus binary to ask for each case's critical step "
                        "(listed in cases.txt) and, with --auto, the advised step, so that "
                        "probes and frames can be placed in steps; without it --auto writes "
                        "'step: auto' and probes every 0.01 s / --auto-guess steps")
    parser.add_argument("--where-above", type=float, default=None, metavar="DT",
                        help="with --auto and --talus: only the shapes whose critical step is "
                             "below DT (where talus refuses DT without --allow-unstable-step)")
    parser.add_argument("--auto-guess", type=float, default=3e-6,
                        help="with --auto and no --talus: the step assumed for spacing probes, s")
    parser.add_argument("--probe-interval", type=float, default=0.01, help="s between probes")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--shapes", default=",".join(SHAPES),
                        help="comma-separated subset of " + ", ".join(SHAPES))
    parser.add_argument("--laws", default="volume,volume_paper",
                        help="comma-separated subset of volume, volume_paper")
    parser.add_argument("--tag", default=None, help="suffix of the case names (default: 'auto' "
                        "with --auto, none otherwise)")
    args = parser.parse_args()

    shapes = [s for s in args.shapes.split(",") if s]
    laws = [law for law in args.laws.split(",") if law]
    for s in shapes:
        if s not in SHAPES:
            parser.error(f"unknown shape '{s}'; expected some of {', '.join(SHAPES)}")
    for law in laws:
        if law not in ("volume", "volume_paper"):
            parser.error(f"unknown law '{law}'; expected volume or volume_paper")
    if args.where_above is not None and not (args.auto and args.talus):
        parser.error("--where-above needs --auto and --talus")
    tag = args.tag if args.tag is not None else ("auto" if args.auto else "")
    columns, layers = lattice_layout(args.particles, args.columns)
    os.makedirs(args.out, exist_ok=True)

    lines = []
    for shape in shapes:
        for law in laws:
            if law == "volume_paper" and (args.auto or shape not in PAPER_LAW_SHAPES):
                continue
            case = "_".join(p for p in (shape, law, tag) if p)
            spec = SHAPES[shape]
            crit = critical_step(args.talus, spec, law, args) if args.talus else None
            if args.auto and args.where_above is not None and not crit < args.where_above:
                continue
            if args.auto and crit:
                dt = advised_step(args.talus, spec, law, crit, args)
                dt_text, steps = repr(dt), round(args.end / dt)
            elif args.auto:
                dt_text, steps = "auto", None
            else:
                dt_text, steps = repr(args.dt), round(args.end / args.dt)
            with open(os.path.join(args.out, case + ".yaml"), "w") as f:
                f.write(scene_text(case, spec, law, dt_text, steps, args, columns, layers,
                                   " (0.2 of dt_crit, what step: auto takes)"
                                   if args.auto and crit else ""))
            lines.append(f"{case} {shape} {law} {dt_text} {crit!r}")
    with open(os.path.join(args.out, "cases.txt"), "w") as f:
        f.write("# case shape law dt dt_crit (None: not asked, no --talus)\n")
        f.write("\n".join(lines) + "\n")
    print(f"make_scenes.py: {len(lines)} scenes of {columns * columns * layers} particles "
          f"({columns} x {columns} x {layers}) in {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
