#!/usr/bin/python3
"""The method paper's §4.1 silo deposition: mineral particles fed from the top of a silo whose
cylindrical wall is corrugated, at a stated scale of the paper's silo (README.md).

    /usr/bin/python3 experiments/silo/silo.py --talus build/talus --output scratch/silo \\
        [--scale 0.4] [--backend cuda] [--quick] [--time-limit S]
    /usr/bin/python3 experiments/silo/silo.py --continue scratch/silo [--time-limit S]
    /usr/bin/python3 experiments/silo/silo.py --analyse scratch/silo

--time-limit S stops talus after S seconds with a checkpoint and exits with status 3 (a run
longer than one of the GPU machine's ten-minute calls); --continue OUTPUT resumes it, and
analyses the silo once the run has ended (../beds/sittings.py).

writes, in OUTPUT: silo.obj (the wall mesh), scene.yaml, talus's outputs (run/), run.json (the
step, the sittings and their commands, whether the run has ended), silo.json (the
mesh's facets, the particles, the wall stage's share of the step, the facets near each particle
at the wall, how the wall layer follows the corrugation, the cost per step and the full run
projected from it), silo.md and silo.png (a slice through the axis: the packing against the
corrugated wall).
"""
import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "experiments", "beds"))
import analyze as beds  # noqa: E402  (frames_of, read_frame)
from sittings import run_sitting, write_atomically  # noqa: E402

# §4.1: "a total height of 10.6 m ... a diameter of 2.1 m ... the hopper outlet, with an opening
# diameter of 0.67 m ... corrugated sidewalls ... approximately 150,000 triangular facets ... about
# 1,000,000 polyhedral particles ... fed from the top ... approximately 50 s."
PAPER = {"height_m": 10.6, "diameter_m": 2.1, "outlet_diameter_m": 0.67, "facets": 150000,
         "particles": 1000000, "feed_seconds": 50.0}
# Not in the paper, stated here: the hopper's wall 30 degrees from the vertical; the corrugation
# a sine of 0.1 m pitch and 0.025 m depth along the height (a corrugated steel silo's profile,
# about a particle deep), 8 rows a pitch and 96 sides: 146,000 facets at full size; the outlet
# closed (a deposition); the particles' circumscribed diameter 0.03 m (1e6 of them then fill the
# hopper and some 3 m of the bin at a packing fraction of 0.6).
GEOMETRY = {"hopper_angle_deg": 30.0, "pitch_m": 0.1, "depth_m": 0.025, "rows_per_pitch": 8,
            "segments": 96, "particle_m": 0.03}
MATERIAL = ("mineral: {density: 2600, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.5,"
            " restitution: 0.3}")
# CI's size: a silo of 0.08 of the paper's (0.85 m tall, 2.8 particles across), 20 particles fed
# over 0.3 s, 0.9 s in all.
QUICK = {"scale": 0.08, "particles": 20, "feed_seconds": 0.3, "settle_seconds": 0.2}


def silo_dimensions(scale):
    r_bin = scale * PAPER["diameter_m"] / 2
    r_out = scale * PAPER["outlet_diameter_m"] / 2
    hopper = (r_bin - r_out) / math.tan(math.radians(GEOMETRY["hopper_angle_deg"]))
    return {"radius": r_bin, "outlet_radius": r_out, "hopper_height": hopper,
            "height": scale * PAPER["height_m"]}


def corrugated_radius(z, dims):
    """The bin wall's radius at height z: a raised cosine of depth `depth_m` and period
    `pitch_m` outward of the bin's radius, from the top of the hopper up."""
    u = (z - dims["hopper_height"]) / GEOMETRY["pitch_m"]
    return dims["radius"] + GEOMETRY["depth_m"] / 2 * (1 - np.cos(2 * np.pi * u))


def silo_mesh(dims):
    """Vertices (n, 3) and triangles (m, 3) of the silo: the closed outlet's disk, the hopper's
    cone (6 rings) and the corrugated bin, every normal pointing into the silo."""
    n = GEOMETRY["segments"]
    theta = 2 * np.pi * np.arange(n) / n
    rings = [(0.0, dims["outlet_radius"])]
    for k in range(1, 7):  # the cone
        f = k / 6
        rings.append((f * dims["hopper_height"],
                      dims["outlet_radius"] + f * (dims["radius"] - dims["outlet_radius"])))
    bin_height = dims["height"] - dims["hopper_height"]
    rows = max(1, round(bin_height / GEOMETRY["pitch_m"] * GEOMETRY["rows_per_pitch"]))
    for k in range(1, rows + 1):
        z = dims["hopper_height"] + bin_height * k / rows
        rings.append((z, float(corrugated_radius(z, dims))))
    vertices = [[0.0, 0.0, 0.0]]  # the disk's centre
    for z, r in rings:
        vertices += [[r * math.cos(t), r * math.sin(t), z] for t in theta]
    vertices = np.array(vertices)
    tris = [[0, 1 + j, 1 + (j + 1) % n] for j in range(n)]  # the disk
    for k in range(len(rings) - 1):
        a, b = 1 + k * n, 1 + (k + 1) * n
        for j in range(n):
            jn = (j + 1) % n
            tris += [[a + j, a + jn, b + j], [a + jn, b + jn, b + j]]
    tris = np.array(tris)
    # Each triangle wound so that its normal points into the silo: up for the disk, towards the
    # axis for the walls (the side where particles live, docs/scenes.md "Normals").
    p = vertices[tris]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    centre = p.mean(axis=1)
    inward = np.where(np.arange(len(tris))[:, None] < n, [0.0, 0.0, 1.0],
                      -np.stack([centre[:, 0], centre[:, 1], np.zeros(len(tris))], axis=1))
    flip = np.einsum("ij,ij->i", normal, inward) < 0
    tris[flip] = tris[flip][:, [0, 2, 1]]
    return vertices, tris


def write_obj(path, vertices, tris):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(f"# The corrugated silo of experiments/silo/silo.py: {len(tris)} triangles\n")
        for v in vertices:
            f.write(f"v {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
        for t in tris:
            f.write(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n")
    os.replace(tmp, path)


def scene_text(dims, particles, feed_seconds, settle_seconds, dt):
    d = GEOMETRY["particle_m"]
    # The feed region: a cylinder under the silo's top, inside the bin by a particle.
    feed_height = max(3 * d, 0.1 * dims["height"])
    feed_base = dims["height"] - feed_height - d
    fall = math.sqrt(2 * dims["height"] / 9.81)
    end = feed_seconds + fall + settle_seconds
    step = "auto" if dt is None else repr(dt)
    frame_every = 1000 if dt is None else max(1, round(end / dt))  # the last frame only
    probe_every = 1000 if dt is None else max(1, round(0.05 / dt))
    return f"""# The method paper's §4.1 silo deposition, written by experiments/silo/silo.py.
time: {{step: {step}, end: {end!r}}}
seed: 3

materials:
  # The paper gives no material: a mineral's density, a stiffness softened for DEM.
  {MATERIAL}

templates:
  ore: {{shape: "mineral:{d!r}", material: mineral}}

particles:
  - feed:
      template: ore
      region: {{cylinder: {{base: [0, 0, {feed_base!r}], axis: [0, 0, 1],
                           radius: {dims['radius'] - d!r}, height: {feed_height!r}}}}}
      rate: {particles / feed_seconds!r}
      stop: {feed_seconds!r}
      velocity: [0, 0, -1]
      random_orientation: true

walls:
  - mesh: {{name: silo, file: silo.obj, material: mineral}}

effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true

outputs:
  trajectories: {{every: {frame_every}, directory: frames, format: csv}}
  probes: {{every: {probe_every}, file: probes.csv, quantities: [kinetic_energy, bed_height]}}
  # A run longer than a sitting stops with a checkpoint (--time-limit) and goes on from it.
  checkpoint: {{every: {20 * probe_every}, directory: checkpoints, keep: 1}}
"""


def advised_step(talus, folder, dims, particles, feed_seconds, settle_seconds):
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        path = os.path.join(tmp, "advice.yaml")
        with open(path, "w") as f:
            f.write(scene_text(dims, particles, feed_seconds, settle_seconds, None))
        os.symlink(os.path.join(folder, "silo.obj"), os.path.join(tmp, "silo.obj"))
        out = subprocess.run([talus, "run", path, "--backend", "cpu", "--threads", "1",
                              "--quiet", "--end", "1e-3", "--output", tmp],
                             capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"silo.py: {talus} could not give the time step:\n{out.stderr}")
        return json.loads(out.stdout)["time_step"]


# ---------------------------------------------------------------------------------------------
# Analysis


def facets_near(pos, radius, vertices, tris):
    """For each particle, the facets whose nearest corner lies within its bounding diameter
    (2 r): the facets within reach of its search, about what the wall stage visits."""
    corners = vertices[tris]  # (m, 3, 3)
    lo, hi = corners.min(axis=1), corners.max(axis=1)
    counts = np.zeros(len(pos), dtype=int)
    reach = 2 * radius
    for i, x in enumerate(pos):
        near = np.all((lo <= x + reach) & (hi >= x - reach), axis=1)
        if np.any(near):
            d2 = ((corners[near] - x) ** 2).sum(axis=2).min(axis=1)
            counts[i] = int((d2 <= reach * reach).sum())
    return counts


def analyse(folder, talus):
    info = json.load(open(os.path.join(folder, "silo.json")))
    dims = info["dimensions"]
    frames, _ = beds.frames_of(os.path.join(folder, "run"))
    if not frames:
        return info
    tids, pos, rot = beds.read_frame(frames[max(frames)])
    d = GEOMETRY["particle_m"]
    shape = beds.shape_data(talus, f"mineral:{d!r}", os.path.join(folder, "shapes"))
    r_xy = np.hypot(pos[:, 0], pos[:, 1])
    wall_r = corrugated_radius(pos[:, 2], dims)
    in_bin = pos[:, 2] > dims["hopper_height"]
    result = {"particles": int(len(pos)), "frame_step": int(max(frames)),
              "lowest_z_m": float(pos[:, 2].min()), "highest_z_m": float(pos[:, 2].max()),
              "outside": int(np.sum(in_bin & (r_xy > wall_r)))}
    # The wall layer in the bin: centroids within a particle diameter of the corrugated wall.
    # Binned by the corrugation's phase, their mean distance from the axis against the wall's
    # radius at that phase: a correlation near 1 is the wavy arrangement.
    layer = in_bin & (wall_r - r_xy < d)
    result["wall_layer"] = int(layer.sum())
    if layer.sum() >= 16:
        phase = ((pos[layer, 2] - dims["hopper_height"]) / GEOMETRY["pitch_m"]) % 1.0
        bins = np.floor(phase * 8).astype(int)
        mean_r = [float(r_xy[layer][bins == b].mean()) if np.any(bins == b) else None
                  for b in range(8)]
        wall_at = [float(dims["radius"] + GEOMETRY["depth_m"] / 2 *
                         (1 - math.cos(2 * math.pi * (b + 0.5) / 8))) for b in range(8)]
        ok = [b for b in range(8) if mean_r[b] is not None]
        corr = (float(np.corrcoef([mean_r[b] for b in ok], [wall_at[b] for b in ok])[0, 1])
                if len(ok) >= 3 else None)
        result["corrugation"] = {"phase_bins": 8, "mean_radius_m": mean_r,
                                 "wall_radius_m": wall_at, "correlation": corr}
    # The facets within reach of the particles at the wall (the paper: about 300 a particle).
    vertices, tris = silo_mesh(dims)
    wall_touching = (wall_r - r_xy < 1.5 * shape["radius"]) | (pos[:, 2] < dims["hopper_height"])
    if np.any(wall_touching):
        counts = facets_near(pos[wall_touching], shape["radius"], vertices, tris)
        result["facets_near_wall_particles"] = {"mean": float(counts.mean()),
                                                "max": int(counts.max()),
                                                "particles": int(wall_touching.sum())}
    info["result"] = result
    write_atomically(os.path.join(folder, "silo.json"), json.dumps(info, indent=1))
    write_report(folder, info, pos, dims)
    return info


def write_report(folder, info, pos, dims):
    r = info["result"]
    run = info["run"]
    lines = ["# The §4.1 silo deposition", "",
             f"talus commit `{info['commit']}`, {info['machine']}, backend `{run['backend']}`. "
             f"Command: `{info['command']}`.", "",
             "| | |", "|---|---|",
             f"| scale of the paper's silo | {info['scale']} (height {dims['height']:.3f} m, "
             f"radius {dims['radius']:.4f} m, outlet radius {dims['outlet_radius']:.4f} m) |",
             f"| wall mesh | {info['facets']} triangles (the paper's silo: about 150,000) |",
             f"| particles at the end | {r['particles']} (fed {info['particles_fed']}), "
             f"{r['outside']} outside the wall |",
             f"| time step, steps, wall time | {run['time_step_s']:.3g} s, {run['steps']}, "
             f"{run['wall_seconds']:.0f} s in {run.get('sittings', 1)} sitting(s) |",
             f"| wall stage's share of the step | {100 * run['wall_share']:.1f} % |"]
    if "facets_near_wall_particles" in r:
        f = r["facets_near_wall_particles"]
        lines.append(f"| facets within a bounding diameter of a wall particle | mean "
                     f"{f['mean']:.1f}, most {f['max']} ({f['particles']} particles) |")
    if r.get("corrugation", {}).get("correlation") is not None:
        lines.append(f"| wall layer's mean radius against the wall's, by corrugation phase | "
                     f"correlation {r['corrugation']['correlation']:.2f} "
                     f"({r['wall_layer']} particles) |")
    if "projection" in info:
        p = info["projection"]
        lines.append(f"| the paper's run projected (1e6 particles, {PAPER['feed_seconds']:.0f} s "
                     f"fed, {p['steps']:.3g} steps) | {p['hours']:.1f} h on this machine at "
                     f"{1e3 * p['seconds_per_step_full']:.1f} ms a step |")
    write_atomically(os.path.join(folder, "silo.md"), "\n".join(lines) + "\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    d = GEOMETRY["particle_m"]
    fig, ax = plt.subplots(figsize=(4.5, 7))
    slab = np.abs(pos[:, 1]) < d
    ax.scatter(pos[slab, 0], pos[slab, 2], s=6, c=pos[slab, 2], cmap="viridis")
    z = np.linspace(0, dims["height"], 2000)
    wall = np.where(z < dims["hopper_height"],
                    dims["outlet_radius"] + z / dims["hopper_height"] *
                    (dims["radius"] - dims["outlet_radius"]), corrugated_radius(z, dims))
    for side in (-1, 1):
        ax.plot(side * wall, z, color="0.3", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x, m (a slice |y| < d)")
    ax.set_ylabel("z, m")
    ax.set_title(f"silo at scale {info['scale']}: {r['particles']} particles")
    fig.tight_layout()
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".silo.", suffix=".png")
    os.close(fd)
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, os.path.join(folder, "silo.png"))
    plt.close(fig)


def git_commit():
    try:
        return subprocess.run(["git", "-C", REPO, "rev-parse", "--short=12", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--talus", default=os.path.join(REPO, "build", "talus"))
    p.add_argument("--output", metavar="DIR")
    p.add_argument("--analyse", metavar="DIR")
    p.add_argument("--scale", type=float, default=0.4,
                   help="of the paper's silo (particles as many as fill it alike: scale^3 of 1e6)")
    p.add_argument("--backend", choices=("cpu", "cuda"), default="cpu")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--quick", action="store_true", help="CI's size")
    p.add_argument("--time-limit", type=float, default=None, metavar="S",
                   help="stop talus after S seconds with a checkpoint (exit status 3)")
    p.add_argument("--continue", dest="resume", metavar="DIR",
                   help="resume the run in DIR that --time-limit stopped, then analyse it")
    args = p.parse_args()
    if args.analyse:
        analyse(args.analyse, args.talus)
        print(open(os.path.join(args.analyse, "silo.md")).read())
        return 0
    if args.resume:
        return go_on(args.resume, args.time_limit)
    if not args.output:
        p.error("give --output DIR (or --continue DIR, --analyse DIR)")
    scale = QUICK["scale"] if args.quick else args.scale
    particles = QUICK["particles"] if args.quick else round(PAPER["particles"] * scale ** 3)
    feed_seconds = QUICK["feed_seconds"] if args.quick else PAPER["feed_seconds"] * scale
    settle = QUICK["settle_seconds"] if args.quick else 2.0
    dims = silo_dimensions(scale)
    os.makedirs(args.output, exist_ok=True)
    vertices, tris = silo_mesh(dims)
    write_obj(os.path.join(args.output, "silo.obj"), vertices, tris)
    dt = advised_step(args.talus, args.output, dims, particles, feed_seconds, settle)
    scene = os.path.join(args.output, "scene.yaml")
    write_atomically(scene, scene_text(dims, particles, feed_seconds, settle, dt))
    argv = [args.talus, "run", scene, "--backend", args.backend, "--quiet", "--output",
            os.path.join(args.output, "run"), "--overwrite"]
    if args.backend == "cpu":
        argv += ["--threads", str(args.threads)]
    info = {"experiment": "method paper section 4.1, silo deposition", "commit": git_commit(),
            "machine": f"{platform.node()}, {os.cpu_count()} CPUs", "scale": scale,
            "command": " ".join([os.path.relpath(sys.argv[0], REPO)] + sys.argv[1:]),
            "talus": args.talus, "backend": args.backend, "threads": args.threads,
            "time_step_s": dt,
            "settle_seconds": settle, "dimensions": dims, "geometry": GEOMETRY,
            "facets": int(len(tris)), "particles_fed": particles, "feed_seconds": feed_seconds,
            "sittings": 0, "run_wall_seconds": 0.0}
    return sit(args.output, info, argv, args.time_limit)


def go_on(folder, time_limit):
    """--continue: resumes the run that a time limit stopped, from its newest checkpoint."""
    info_path = os.path.join(folder, "run.json")
    if not os.path.exists(info_path):
        sys.exit(f"silo.py: {info_path} does not exist: --continue takes the --output folder of "
                 "an earlier call")
    info = json.load(open(info_path))
    if info.get("finished"):
        analyse(folder, info["talus"])
        print(open(os.path.join(folder, "silo.md")).read())
        return 0
    argv = [info["talus"], "run", "--resume", os.path.join(folder, "run", "checkpoints"),
            "--backend", info["backend"], "--quiet"]
    if info["backend"] == "cpu":
        argv += ["--threads", str(info["threads"])]
    return sit(folder, info, argv, time_limit)


def sit(folder, info, argv, time_limit):
    """One sitting of the run; once the run has ended, its costs, the projection and the
    analysis."""
    summary = run_sitting(argv, info, os.path.join(folder, "run.json"), time_limit, "silo.py")
    if summary is None:
        print(f"silo.py: continue with --continue {folder}")
        return 3
    # The stage times are the last sitting's (each sitting's are in run.json's sitting_steps):
    # the bed at its fullest, what the projection wants. Seconds a step: every sitting's wall
    # seconds (their setups included) over every step.
    stages = summary.get("stage_seconds", {})
    work = sum(v for k, v in stages.items() if k != "output")
    dt = info["time_step_s"]
    run = {"backend": info["backend"], "time_step_s": dt, "steps": summary["steps"],
           "sittings": info["sittings"], "wall_seconds": info["run_wall_seconds"],
           "stage_seconds": stages,
           "stage_steps": summary["steps"] - summary.get("resumed_from_step", 0),
           "wall_share": stages.get("wall_contacts", 0) / work if work > 0 else 0,
           "seconds_per_step": info["run_wall_seconds"] / max(1, summary["steps"])}
    info["run"] = run
    # The paper's run projected from this one's cost: the step's cost grows with the particles
    # (the final count here; most of the run has fewer), the steps with the simulated time at the
    # same step.
    final = summary.get("particles") or info["particles_fed"]
    full_steps = (PAPER["feed_seconds"] + math.sqrt(2 * PAPER["height_m"] / 9.81)
                  + info["settle_seconds"]) / dt
    per_step = run["seconds_per_step"] * PAPER["particles"] / max(1, final)
    info["projection"] = {"steps": full_steps, "seconds_per_step_full": per_step,
                          "hours": full_steps * per_step / 3600,
                          "basis": "seconds a step scaled by 1e6 over the final particles"}
    write_atomically(os.path.join(folder, "silo.json"), json.dumps(info, indent=1))
    analyse(folder, info["talus"])
    print(open(os.path.join(folder, "silo.md")).read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
