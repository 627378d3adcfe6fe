#!/usr/bin/python3
"""The Platonic shape study: poured and tapped beds of the five Platonic solids and of spheres,
at three friction coefficients, and the packing fraction in the core of each bed, measured on
the true shapes (random points; README.md says why and how).

Each case (shape, friction) is one talus run: a lattice of randomly oriented particles falls into
an open box and settles until --pour s (the "poured" bed: the frame at that time), then the box
is shaken up and down (a raised-cosine oscillation, `motion: oscillation`, of peak acceleration
Gamma g at --frequency Hz for --cycles cycles) and the bed settles again (the "tapped" bed: the
last frame).

    /usr/bin/python3 experiments/platonic_packing/platonic_packing.py --talus build/talus \\
        --output scratch/platonic [--backend cuda] [--jobs N] [--quick] [--time-limit S] \\
        [--no-analysis]
    /usr/bin/python3 experiments/platonic_packing/platonic_packing.py --analyse scratch/platonic

writes, in OUTPUT: one folder a case (scene.yaml, talus's outputs), study.json (every case's
packing fractions with their errors, the commands, machine and commit), study.md (the table) and
study.png (packing fraction against the number of faces, a line a friction, poured and tapped).
--jobs N runs N cases at once (with --backend cuda, each on a GPU of its own through
CUDA_VISIBLE_DEVICES: one run a GPU), the longest first. A case whose folder holds a finished run
is not run again. --time-limit S: no case runs past S seconds from the start (talus stops it with
a checkpoint, ../beds/sittings.py; a case not begun with a second left waits) and the driver
exits with status 3; the same command again goes on, each unfinished case from its checkpoint. --no-analysis: run the cases and write
study.json, but leave the analysis to a later --analyse (e.g. on another machine).
--quick is CI's size: two shapes, one friction, a few dozen particles, short times.
"""
import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import queue
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "experiments", "beds"))
import analyze as beds  # noqa: E402  (shape_data, frames_of, read_frame, inside_mask)
from sittings import run_sitting, write_atomically  # noqa: E402

# The shapes by their number of faces (the figure's abscissa); spheres drawn apart.
SHAPES = {"tetrahedron": 4, "cube": 6, "octahedron": 8, "dodecahedron": 12, "icosahedron": 20,
          "sphere": None}
D = 0.01  # m, every particle's circumscribed diameter
# The beds' material (that of experiments/beds, but for the friction): density 1200 kg/m^3,
# E = 5 MPa, nu = 0.3, restitution 0.5.
MATERIAL = {"density": 1200, "youngs_modulus": 5.0e6, "poisson_ratio": 0.3, "restitution": 0.5}
# Spheres touch walls only under the linear law (the volume law has no sphere-wall overlap): K_N
# keeps the bottom layer's overlap below 0.1 % of d under 30 layers (6e-3 N a particle: 0.2 N,
# 1e-5 m at 2e4 N/m); eta = 1 N s/m gives a restitution of about 0.5 for two of them
# (zeta = eta / (2 sqrt(K m/2)) = 0.2 at m = 6.3e-4 kg); the tangential damping as much.
SPHERE_LAW = "{model: linear, stiffness: 2.0e4, damping: 1.0, tangential_damping: 1.0}"
FRICTIONS = (0.1, 0.4, 0.8)

# Each shape's volume over d^3 (d the circumscribed diameter): 8 / (9 sqrt 3), (2 / sqrt 3)^3,
# 4 / 3, 2.7852, 2.5362 and 4 pi / 3 times (d / 2)^3.
VOLUME_D3 = {"tetrahedron": 0.064150, "cube": 0.192450, "octahedron": 0.166667,
             "dodecahedron": 0.348145, "icosahedron": 0.317019, "sphere": 0.523599}
# Full size: 10 x 10 columns 1.05 d apart (a box 10.5 d wide), and as many layers as a bed
# `bed_d` diameters deep needs at a packing fraction of about `packing_guess` (a layer of the
# lattice, columns^2 particles of v d^3 in a box (1.05 columns d)^2 wide, makes v d / (phi 1.05^2)
# of bed), at least `layers`: the core then leaves out 2 d at the floor and 2 d under the
# surface and keeps 6.
# Equal counts do not do: 3,000 tetrahedra (0.064 d^3 each) made a bed 3.3 d deep on the GPU,
# no core at all, where 3,000 spheres stand 26 d. So 95 layers of tetrahedra (9,500), 32 of
# cubes, 37 of octahedra, 30 of the rest. Poured until 1 s or until the lattice's top layer has
# fallen to the floor and 0.6 s more, whichever is later (the tetrahedra's lattice is 1 m tall:
# 1.05 s); 20 cycles at 30 Hz of Gamma = 2, then 0.4 s to settle.
FULL = {"columns": 10, "layers": 30, "bed_d": 10.0, "packing_guess": 0.55, "pour": 1.0,
        "frequency": 30.0, "gamma": 2.0, "cycles": 20, "rest": 0.4, "shapes": list(SHAPES),
        "frictions": list(FRICTIONS), "points": 400000}
# CI's size: two shapes, one friction, 4 x 4 x 8, short times (the driver end to end, not
# numbers to read: the beds are 2 to 6 d deep, the core half a diameter in from everything).
QUICK = {"columns": 4, "layers": 8, "pour": 0.2, "frequency": 40.0, "gamma": 2.0, "cycles": 2,
         "rest": 0.06, "shapes": ["cube", "sphere"], "frictions": [0.4], "points": 40000}
# The core: a box inside the bed, this many diameters in from the side walls, the floor and the
# free surface (the walls order the particles next to them: experiments/beds/README.md).
INSETS = {"wall": 2.0, "floor": 2.0, "surface": 2.0}
QUICK_INSETS = {"wall": 0.5, "floor": 0.5, "surface": 0.5}
G = 9.81


def case_name(shape, friction):
    return f"{shape}_mu{friction:g}"


def amplitude(size):
    """The raised cosine's amplitude A for peak acceleration Gamma g: A (2 pi f)^2 = Gamma g."""
    return size["gamma"] * G / (2 * math.pi * size["frequency"]) ** 2


def layers_for(shape, size):
    """The lattice's layers of `shape`: FULL's bed of bed_d diameters (above), else size's."""
    if "bed_d" not in size:
        return size["layers"]
    need = size["bed_d"] * size["packing_guess"] * 1.05 ** 2 / VOLUME_D3[shape]
    return max(size["layers"], math.ceil(need))


def pour_for(shape, size):
    """The pour's end, s: size's, or (full size) the top layer's fall and 0.6 s if later."""
    if "bed_d" not in size:
        return size["pour"]
    top = layers_for(shape, size) * 1.05 * D
    return max(size["pour"], round(math.sqrt(2 * top / G) + 0.6, 2))


def end_time(size, shape):
    return pour_for(shape, size) + size["cycles"] / size["frequency"] + size["rest"]


def scene_text(shape, friction, size, dt_text, frame_every, columns=None, layers=None):
    columns = columns or size["columns"]
    layers = layers or layers_for(shape, size)
    pour = pour_for(shape, size)
    spacing = 1.05 * D  # no two bounding spheres touch at the start, whatever the orientations
    width, top = columns * spacing, layers * spacing
    slack = 1e-9  # the region a hair larger than the lattice, so no layer is rounded away
    template = (f"{{sphere: {D / 2!r}, material: grain}}" if shape == "sphere"
                else f'{{shape: "{shape}:{D!r}", material: grain}}')
    law = SPHERE_LAW if shape == "sphere" else "volume"
    m = MATERIAL
    return f"""\
# The Platonic shape study (experiments/platonic_packing): {columns * columns * layers} {shape}s
# of {D} m poured from a {columns} x {columns} x {layers} lattice into an open box, friction
# {friction}; settled until {pour} s, then the box shaken {size['cycles']} cycles at
# {size['frequency']} Hz, peak acceleration {size['gamma']} g, and left to settle.
time: {{step: {dt_text}, end: {end_time(size, shape)!r}}}
seed: 7

materials:
  grain: {{density: {m['density']}, youngs_modulus: {m['youngs_modulus']},
          poisson_ratio: {m['poisson_ratio']}, friction: {friction!r},
          restitution: {m['restitution']}}}

templates:
  grain: {template}

particles:
  - lattice:
      template: grain
      region: {{box: {{min: [0, 0, 0],
                      max: [{width * (1 + slack)!r}, {width * (1 + slack)!r},
                            {top * (1 + slack)!r}]}}}}
      spacing: {spacing!r}
      random_orientation: true
      seed: 7

walls:
  - box:
      name: box
      min: [0, 0, 0]
      max: [{width!r}, {width!r}, {top + spacing!r}]
      open_top: true
      material: grain
      motion:
        oscillation: {{direction: [0, 0, 1], amplitude: {amplitude(size)!r},
                      frequency: {size['frequency']!r}, start: {pour!r},
                      cycles: {size['cycles']}}}

effects:
  gravity: [0, 0, -{G}]
  contact: {law}
  friction: true
  rotation: true

outputs:
  trajectories: {{every: {frame_every}, directory: frames}}
  probes: {{every: {max(1, frame_every // 50)}, file: probes.csv,
           quantities: [kinetic_energy, energy, contact_count, bed_height]}}
  # A run that a time limit stops writes its checkpoint there and goes on from it.
  checkpoint: {{every: {frame_every}, directory: checkpoints, keep: 1}}
"""


def advised_step(talus, shape, friction, size):
    """What `step: auto` takes for the case (0.2 of the critical step talus estimates), from a
    tiny copy of the scene (the advisor depends on the templates, materials, law and walls, not
    on the count)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "advice.yaml")
        with open(path, "w") as f:
            f.write(scene_text(shape, friction, size, "auto", 1, columns=2, layers=1))
        out = subprocess.run([talus, "run", path, "--backend", "cpu", "--threads", "1",
                              "--quiet", "--end", "1e-3", "--output", tmp],
                             capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"platonic_packing.py: {talus} could not give the time step for {shape}:\n"
                     f"{out.stderr}")
        return json.loads(out.stdout)["time_step"]


def run_case(talus, shape, friction, size, out, backend, device, threads, deadline):
    """Writes the case's scene (at the advised step, frames at the end of the pour) and runs it
    unless a finished run is there, for at most until `deadline` (time.monotonic(); None: no
    limit), going on from the checkpoint of a run that an earlier deadline stopped. Returns the
    case's record, or None when the deadline stopped it."""
    name = case_name(shape, friction)
    folder = os.path.join(out, name)
    record_path = os.path.join(folder, "case.json")
    if os.path.exists(record_path):
        return json.load(open(record_path))
    # No sitting starts with less than a second left; one that does start runs until the
    # deadline even when its setup (the advised step, the scene) used some of that second.
    if deadline is not None and deadline - time.monotonic() < 1:
        return None
    os.makedirs(folder, exist_ok=True)
    info_path = os.path.join(folder, "run.json")
    checkpoints = os.path.join(folder, "run", "checkpoints")
    if os.path.exists(info_path) and os.path.isdir(checkpoints) and os.listdir(checkpoints):
        info = json.load(open(info_path))
        argv = [talus, "run", "--resume", checkpoints, "--backend", backend, "--quiet"]
    else:
        dt = advised_step(talus, shape, friction, size)
        pour_steps = round(pour_for(shape, size) / dt)
        scene = os.path.join(folder, "scene.yaml")
        write_atomically(scene, scene_text(shape, friction, size, repr(dt), pour_steps))
        argv = [talus, "run", scene, "--backend", backend, "--quiet", "--output",
                os.path.join(folder, "run"), "--overwrite"]
        info = {"time_step_s": dt, "pour_step": pour_steps, "pour_s": pour_for(shape, size),
                "layers": layers_for(shape, size)}
    if backend == "cpu":
        argv += ["--threads", str(threads)]
    env = dict(os.environ)
    if device is not None:
        env["CUDA_VISIBLE_DEVICES"] = str(device)
    # talus stops at the first step boundary after the limit, with a checkpoint, however small.
    limit = None if deadline is None else max(deadline - time.monotonic(), 0.05)
    summary = run_sitting(argv, info, info_path, limit, f"platonic_packing.py: {name}", env=env)
    if summary is None:
        return None
    record = {"case": name, "shape": shape, "faces": SHAPES[shape], "friction": friction,
              "time_step_s": info["time_step_s"], "pour_step": info["pour_step"],
              "pour_s": info.get("pour_s"), "layers": info.get("layers"),
              "steps": summary.get("steps"), "particles": summary.get("particles"),
              "wall_seconds": info["run_wall_seconds"], "sittings": info["sittings"],
              "backend": backend, "command": info["commands"][0],
              "continued_by": info["commands"][1:]}
    write_atomically(record_path, json.dumps(record, indent=1) + "\n")
    return record


# ---------------------------------------------------------------------------------------------
# The packing fraction of the core


def sphere_inside(points, pos, radius):
    """Which points lie inside any of the spheres (grid buckets as beds.inside_mask)."""
    inside = np.zeros(len(points), dtype=bool)
    cell = 2 * radius
    lo = points.min(axis=0)
    ijk = np.floor((points - lo) / cell).astype(int)
    buckets = {}
    for k, key in enumerate(map(tuple, ijk)):
        buckets.setdefault(key, []).append(k)
    for x in pos:
        a = np.floor((x - radius - lo) / cell).astype(int)
        b = np.floor((x + radius - lo) / cell).astype(int)
        idx = [k for i in range(a[0], b[0] + 1) for j in range(a[1], b[1] + 1)
               for m in range(a[2], b[2] + 1) for k in buckets.get((i, j, m), [])]
        if idx:
            idx = np.array(idx)
            rel = points[idx] - x
            inside[idx[np.einsum("ij,ij->i", rel, rel) <= radius * radius]] = True
    return inside


def shape_of(talus, shape, cache):
    if shape == "sphere":
        r = D / 2
        return {"sphere": True, "radius": r, "volume": 4 / 3 * math.pi * r ** 3,
                "vertices": np.array([[0, 0, r]])}
    return beds.shape_data(talus, f"{shape}:{D!r}", cache)


def core_packing(frame, box_width, shape, insets, points, seed):
    """The packing fraction in the core box of a frame: random points, the fraction inside the
    true shapes. Its error: the larger of the binomial one (the points) and the spread of the
    core's eight octants (the bed's own variation, which more points do not shrink)."""
    tids, pos, rot = beds.read_frame(frame)
    tops = pos[:, 2] + (rot[:, 2, :] @ shape["vertices"].T).max(axis=1)
    # The free surface: the median over columns one diameter wide of the highest top.
    cols = {}
    for key, z in zip(map(tuple, np.floor(pos[:, :2] / D).astype(int)), tops):
        cols[key] = max(cols.get(key, -np.inf), z)
    surface = float(np.median(list(cols.values())))
    # The floor at z = 0: the frames are taken with the box at rest (the end of the pour, before
    # the first cycle; the end, after the last).
    lo = np.array([insets["wall"] * D, insets["wall"] * D, insets["floor"] * D])
    hi = np.array([box_width - insets["wall"] * D, box_width - insets["wall"] * D,
                   surface - insets["surface"] * D])
    result = {"surface_m": surface, "core_min_m": lo.tolist(), "core_max_m": hi.tolist(),
              "core_height_d": float((hi[2] - lo[2]) / D), "phi": None, "phi_error": None}
    if np.any(hi <= lo):
        return result  # too shallow a bed for a core
    rng = np.random.default_rng(seed)
    pts = lo + (hi - lo) * rng.random((points, 3))
    if shape.get("sphere"):
        inside = sphere_inside(pts, pos, shape["radius"])
    else:
        inside = beds.inside_mask(pts, tids, pos, rot, {t: shape for t in set(tids)})
    phi = float(inside.mean())
    binomial = math.sqrt(phi * (1 - phi) / points)
    mid = (lo + hi) / 2
    octant = ((pts > mid) * np.array([1, 2, 4])).sum(axis=1)
    parts = [inside[octant == k].mean() for k in range(8) if np.any(octant == k)]
    spread = float(np.std(parts, ddof=1) / math.sqrt(len(parts))) if len(parts) > 1 else 0.0
    result.update(phi=phi, phi_error=max(binomial, spread), binomial_error=binomial,
                  octant_error=spread, points=points)
    return result


def volume_check(frame, shape, points, seed):
    """The random points' solid fraction in the box around every particle times its volume, over
    the particles' summed volume: 1 within the sampling error (and the contacts' overlaps) when
    the frames, the rotations and the inside test are right."""
    tids, pos, rot = beds.read_frame(frame)
    r = shape["radius"]
    lo, hi = pos.min(axis=0) - r, pos.max(axis=0) + r
    pts = lo + (hi - lo) * np.random.default_rng(seed).random((points, 3))
    if shape.get("sphere"):
        f = float(sphere_inside(pts, pos, r).mean())
    else:
        f = float(beds.inside_mask(pts, tids, pos, rot, {t: shape for t in set(tids)}).mean())
    summed = len(tids) * shape["volume"]
    return {"found_over_summed": f * float(np.prod(hi - lo)) / summed,
            "error": math.sqrt((1 - f) / (f * points)) if f > 0 else math.inf}


def wall_work(folder):
    """The walls' work on the particles by the end (the energy probe's last row), J."""
    path = os.path.join(folder, "probes.csv")
    rows = beds.read_probes(path)
    return float(rows["wall_work"][-1]) if rows and "wall_work" in rows else None


def analyse_case(out, record, size, insets, talus, points):
    folder = os.path.join(out, record["case"], "run")
    frames, _ = beds.frames_of(folder)
    if not frames:
        return record
    last = max(frames)
    poured = min(frames, key=lambda s: abs(s - record["pour_step"]))
    shape = shape_of(talus, record["shape"], os.path.join(out, "shapes"))
    width = size["columns"] * 1.05 * D
    record = dict(record)
    record["poured"] = core_packing(frames[poured], width, shape, insets, points, 11)
    record["poured"]["step"] = poured
    record["tapped"] = core_packing(frames[last], width, shape, insets, points, 12)
    record["tapped"]["step"] = last
    record["volume_check"] = volume_check(frames[last], shape, points, 13)
    record["wall_work_J"] = wall_work(folder)
    return record


# ---------------------------------------------------------------------------------------------
# Report


def git_commit():
    try:
        return subprocess.run(["git", "-C", REPO, "rev-parse", "--short=12", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def machine(backend):
    text = f"{platform.node()}, {os.cpu_count()} CPUs"
    if backend == "cuda":
        try:
            gpus = subprocess.run(["nvidia-smi", "--query-gpu=name", "--format=csv,noheader"],
                                  capture_output=True, text=True, check=True).stdout.split("\n")
            names = [g for g in gpus if g.strip()]
            text += f", {len(names)} x {names[0]}" if names else ""
        except (OSError, subprocess.CalledProcessError):
            pass
    return text


def fmt(v, e):
    return "—" if v is None else f"{v:.3f} ± {e:.3f}"


def markdown(study):
    size = study["size"]
    lines = [
        "# The Platonic shape study: packing fractions", "",
        f"talus commit `{study['commit']}`, {study['machine']}, backend `{study['backend']}`. "
        f"Command: `{study['command']}`. Beds of {size['columns']} x {size['columns']} columns "
        f"of particles of {D} m circumscribed diameter, "
        + (f"as many layers as a bed {size['bed_d']:g} d deep needs (at least {size['layers']}: "
           "the particles column)" if "bed_d" in size else f"{size['layers']} layers")
        + f"; poured until {size['pour']} s (or the top layer's fall and 0.6 s, if later: "
        f"the pour column), then {size['cycles']} cycles at {size['frequency']} Hz of peak "
        f"acceleration {size['gamma']} g (amplitude {amplitude(size) * 1e3:.3f} mm), settled "
        f"{size['rest']} s. The core: {study['insets']['wall']} d from the side walls, "
        f"{study['insets']['floor']} d above the floor, {study['insets']['surface']} d below the "
        "free surface; the error the larger of the points' binomial one and the spread of the "
        "core's octants.", "",
        "| shape | faces | friction | poured | tapped | core height, d (poured, tapped) | "
        "particles | pour, s | time step, s | run, s |",
        "|---|---|---|---|---|---|---|---|---|---|"]
    for c in study["cases"]:
        p, t = c.get("poured", {}), c.get("tapped", {})
        lines.append(
            f"| {c['shape']} | {c['faces'] or '—'} | {c['friction']:g} | "
            f"{fmt(p.get('phi'), p.get('phi_error'))} | {fmt(t.get('phi'), t.get('phi_error'))} "
            f"| {p.get('core_height_d', math.nan):.1f}, {t.get('core_height_d', math.nan):.1f}"
            f" | {c.get('particles')} | {c.get('pour_s') or study['size']['pour']:g} | "
            f"{c['time_step_s']:.3g} | {c['wall_seconds']:.0f} |")
    return "\n".join(lines) + "\n"


def figure(study, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    colours = {0.1: "tab:blue", 0.4: "tab:orange", 0.8: "tab:green"}
    sphere_x = 26
    for mu in sorted({c["friction"] for c in study["cases"]}):
        for protocol, marker, style in (("poured", "o", "--"), ("tapped", "s", "-")):
            rows = [c for c in study["cases"] if c["friction"] == mu
                    and c.get(protocol, {}).get("phi") is not None]
            solids = sorted((c for c in rows if c["faces"]), key=lambda c: c["faces"])
            spheres = [c for c in rows if not c["faces"]]  # beside the solids, not joined
            colour = colours.get(mu, "k")
            for group, line, label in ((solids, style, f"mu = {mu:g}, {protocol}"),
                                       (spheres, "none", None if solids else
                                        f"mu = {mu:g}, {protocol}")):
                if not group:
                    continue
                ax.errorbar([c["faces"] or sphere_x for c in group],
                            [c[protocol]["phi"] for c in group],
                            yerr=[c[protocol]["phi_error"] for c in group], marker=marker,
                            ls=line, capsize=3, color=colour, label=label)
    ax.set_xscale("log")
    ticks = [4, 6, 8, 12, 20, sphere_x]
    ax.set_xticks(ticks)
    ax.set_xticklabels(["4\ntetra", "6\ncube", "8\nocta", "12\ndodeca", "20\nicosa",
                        "sphere"])
    ax.set_xlabel("number of faces")
    ax.set_ylabel("packing fraction of the core")
    ax.set_title("Platonic solids and spheres: poured and tapped beds")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.text(0.01, 0.01, f"talus {study['commit']}, {study['machine']}", fontsize=6,
             color="0.4")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)


def analyse(out, talus, points=None):
    study = json.load(open(os.path.join(out, "study.json")))
    size = study["size"]
    insets = study["insets"]
    points = points or size["points"]
    study["cases"] = [analyse_case(out, c, size, insets, talus, points) for c in study["cases"]]
    write_atomically(os.path.join(out, "study.json"), json.dumps(study, indent=1) + "\n")
    write_atomically(os.path.join(out, "study.md"), markdown(study))
    figure(study, os.path.join(out, "study.png"))
    return study


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--talus", default=os.path.join(REPO, "build", "talus"))
    p.add_argument("--output", metavar="DIR", help="the study's folder (created)")
    p.add_argument("--analyse", metavar="DIR", help="analyse the runs in DIR again and report")
    p.add_argument("--backend", choices=("cpu", "cuda"), default="cpu")
    p.add_argument("--jobs", type=int, default=1, help="cases run at once (cuda: GPUs)")
    p.add_argument("--threads", type=int, default=1, help="host threads a case (cpu)")
    p.add_argument("--quick", action="store_true", help="CI's size")
    p.add_argument("--shapes", nargs="+", choices=list(SHAPES), default=None)
    p.add_argument("--frictions", nargs="+", type=float, default=None)
    p.add_argument("--time-limit", type=float, default=None, metavar="S",
                   help="stop every case still running S seconds after the start, with a "
                        "checkpoint (exit status 3; the same command again goes on)")
    p.add_argument("--commit", default=None, help="the commit of the talus binary (default: "
                   "this checkout's)")
    p.add_argument("--no-analysis", action="store_true",
                   help="run the cases and write study.json; analyse later with --analyse")
    args = p.parse_args()
    if args.analyse:
        study = analyse(args.analyse, args.talus)
        print(markdown(study))
        return 0
    if not args.output:
        p.error("give --output DIR (or --analyse DIR)")
    size = dict(QUICK if args.quick else FULL)
    if args.shapes:
        size["shapes"] = args.shapes
    if args.frictions:
        size["frictions"] = args.frictions
    insets = QUICK_INSETS if args.quick else INSETS
    os.makedirs(args.output, exist_ok=True)
    # The longest cases first (the shapes in SHAPES' order take ever fewer steps: tetrahedra
    # some 780,000, spheres 61,000), so that the last to finish are short.
    cases = [(s, mu) for s in size["shapes"] for mu in size["frictions"]]
    jobs = max(1, args.jobs)
    # Each running case holds a GPU of its own (a case takes one from the queue and gives it
    # back): two runs never share one, whichever finishes first.
    devices = queue.Queue()
    for k in range(jobs):
        devices.put(k if args.backend == "cuda" and jobs > 1 else None)
    start = time.monotonic()
    deadline = None if args.time_limit is None else start + args.time_limit

    def one(k):
        shape, mu = cases[k]
        device = devices.get()
        try:
            return run_case(args.talus, shape, mu, size, args.output, args.backend, device,
                            args.threads, deadline)
        finally:
            devices.put(device)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        records = list(pool.map(one, range(len(cases))))
    unfinished = [case_name(*c) for c, r in zip(cases, records) if r is None]
    if unfinished:
        print(f"platonic_packing.py: --time-limit {args.time_limit:g} s stopped "
              f"{len(unfinished)} of {len(cases)} cases ({', '.join(unfinished)}); run the same "
              "command again to go on")
        return 3
    study = {"study": "experiments/platonic_packing: poured and tapped beds of the Platonic "
                      "solids and spheres",
             "commit": args.commit or git_commit(), "machine": machine(args.backend), "backend": args.backend,
             "command": " ".join([os.path.relpath(sys.argv[0], REPO)] + sys.argv[1:]),
             "size": size, "insets": insets, "wall_seconds": time.monotonic() - start,
             "cases": records}
    write_atomically(os.path.join(args.output, "study.json"), json.dumps(study, indent=1) + "\n")
    if args.no_analysis:
        print(f"platonic_packing.py: {len(cases)} cases run; analyse with --analyse "
              f"{args.output}")
        return 0
    study = analyse(args.output, args.talus)
    print(markdown(study))
    return 0


if __name__ == "__main__":
    sys.exit(main())
