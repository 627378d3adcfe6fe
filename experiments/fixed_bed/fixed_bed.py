#!/usr/bin/python3
"""The method paper's §4.2 fixed bed: cylindrical catalyst pellets fed into a narrow tube.

Writes the scene (a 25 mm tube, 1.80 m tall, closed at the bottom; pellets of 5.5 mm diameter
and 5.5 mm length, N-sided prisms, fed from the top with random orientations), runs it with
talus, and analyses the bed from its last frame, on the true polyhedra:

  - the mean porosity of the bed away from its ends (random points in the tube between 2 pellet
    diameters above the floor and 2 below the surface), with its sampling error;
  - the radial porosity profile from the wall to the axis (equal-area rings);
  - the orientation of the pellets' axes against the tube's (cos of the angle: uniform for
    random orientations);
  - the bed height as the pellets land (from the frames written while it fills).

    /usr/bin/python3 experiments/fixed_bed/fixed_bed.py --talus build/talus \\
        [--sides 16] [--seed 1] [--pellets N] [--youngs-modulus PA] [--backend auto|cpu|cuda] \\
        [--output scratch/fixed_bed] [--quick] [--points 400000]
    /usr/bin/python3 experiments/fixed_bed/fixed_bed.py --continue OUTPUT [--time-limit S]
    /usr/bin/python3 experiments/fixed_bed/fixed_bed.py --analyse OUTPUT [--talus build/talus]

--time-limit S stops talus after S seconds (its --stop-after: a checkpoint at the next step) and
exits with status 3; --continue OUTPUT resumes that run (with its own --time-limit), and
analyses it once it has ended. After each sitting every frame's line of the filling (step,
pellets, pellets at rest, surface) goes into OUTPUT/filling.json; --prune-frames then removes
every frame but the newest, so that a run of thousands of pellets can be carried between
machines as its checkpoint, filling.json and one frame.

Into OUTPUT (each through a temporary file and a rename): scene.yaml, the run (run/: frames,
probes, vtk, summary.json), bed.json (every number below, the command, the machine), bed.md,
and bed.png (the radial profile, the orientations, the height as the pellets land).
README.md here gives the choices and their reasons. Needs numpy and matplotlib.
"""

import argparse
import glob
import json
import math
import os
import platform
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "experiments", "beds"))
import analyze as beds  # noqa: E402  (frame_arrays, shape_data, inside_mask)
from sittings import run_sitting, write_atomically  # noqa: E402

# §4.2: "cylindrical catalyst particles with an outer diameter of 5.5 mm and a length of 5.5 mm.
# The reactor tube had an inner diameter of 2.5 cm, a total height of 1.80 m, and a packed bed
# height of 1.26 m ... approximately 10,000 cylindrical catalyst particles."
PAPER = {"pellet_diameter_m": 0.0055, "pellet_length_m": 0.0055, "tube_diameter_m": 0.025,
         "tube_height_m": 1.80, "bed_height_m": 1.26, "pellets": 10000}
# The pellets' and the tube's Young's modulus ("youngs", Pa; --youngs-modulus): the pellets land
# at up to 6 m/s and a softer pellet sinks deeper into those it hits, so the bed's porosity rose
# from 0.34 at 1e6 to 0.38 at 1e7 and 0.41 at 1e8 (README, "Stiffness"); the step falls as
# 1/sqrt(E).
# The feed's rate: below what its region can hold as the pellets clear it (FULL: a region 0.5 m
# tall holds about 100 pellets and clears in about 0.17 s at 2 m/s and g: about 600 a second), so
# that every pellet asked for goes in by `stop` and the end time holds the last one's fall.
FULL = {"tube_height": 1.80, "pellets": None, "feed_height": 0.50, "settle": 0.6, "rate": 400,
        "youngs": 1.0e8}
# CI's size: the same tube and pellets, 0.12 m tall, 60 pellets (about 0.03 m of bed).
# Its pellets fall at most 0.12 m and land below 2.5 m/s, and CI affords its steps at E = 1e6.
QUICK = {"tube_height": 0.12, "pellets": 60, "feed_height": 0.04, "settle": 0.10, "rate": 600,
         "youngs": 1.0e6}
# The paper's "approximately 10,000" pellets cannot make its 1.26 m bed: 10,000 pellets of
# 5.5 x 5.5 mm hold 1.31e-3 m^3, 2.1 times the tube's 6.19e-4 m^3 up to 1.26 m. The feed's count
# (FULL) is the one that fills the tube to 1.26 m at the solid fraction these beds reach at the
# default stiffness (README, "Stiffness": 0.59 at E = 1e8 Pa; 0.62 at 1e7, 0.66 at 1e6); the
# report gives the height it reached.
BED_SOLID_FRACTION = 0.59
TUBE_SEGMENTS = 96  # the tube's polygon: its sagitta r (1 - cos(pi/96)) = 6.7 um, 0.1 % of d_p
# The pair list's Verlet skin, m: pellets fall at up to 6 m/s, 0.08 mm a step, so the default
# (a tenth of the bounding diameter, 0.78 mm) rebuilds the list every 5 steps; 4 mm every 25 or
# so, with a few more candidates in a tube 4.5 pellets wide. The trajectories do not depend on it
# (docs/scenes.md): 0.5 s of the full scene on the host gave the same probes and frames to the
# byte, 1258 rebuilds instead of 5818 and 9.5 s instead of 13.5.
SKIN = 0.004


def pellet_volume(sides):
    """The N-sided prism's volume, m^3: its rim on the pellet's circle, (N/2) r^2 sin(2 pi/N) L."""
    r = PAPER["pellet_diameter_m"] / 2
    return sides / 2 * r * r * math.sin(2 * math.pi / sides) * PAPER["pellet_length_m"]


def paper_bed_pellets(sides):
    """The pellets that fill the tube to the paper's bed height at BED_SOLID_FRACTION."""
    tube = math.pi * (PAPER["tube_diameter_m"] / 2) ** 2 * PAPER["bed_height_m"]
    return round(BED_SOLID_FRACTION * tube / pellet_volume(sides))


def pellet_spec(sides):
    return f"cylinder:{PAPER['pellet_diameter_m']},{PAPER['pellet_length_m']},{sides}"


def scene_text(sides, seed, pellets, size, dt, youngs):
    """The scene at time step `dt` (a number, or "auto" for the advice run): the tube, the
    pellets' feed near its top, the outputs the analysis reads."""
    d, length = PAPER["pellet_diameter_m"], PAPER["pellet_length_m"]
    radius = PAPER["tube_diameter_m"] / 2
    bounding = math.hypot(d / 2, length / 2)
    top = size["tube_height"]
    # The feed region: inside the tube by the pellets' bounding radius and 0.3 mm more, below
    # the tube's top by the same; a pellet is placed only where it touches nothing, so the feed
    # inserts as fast as the falling pellets clear the region (docs/scenes.md, "Feed").
    feed_radius = radius - bounding - 0.0003
    feed_base = top - bounding - 0.0003 - size["feed_height"]
    rate = float(size["rate"])
    stop = pellets / rate
    # The last pellets fall the tube's height: sqrt(2 h / g), and then settle.
    end = stop + math.sqrt(2 * top / 9.81) + size["settle"]
    def steps(seconds):
        return max(1, round(seconds / dt)) if dt != "auto" else 1000
    frames = steps(0.1 if size is FULL else 0.02)  # the filling bed, for its height
    step_text = dt if dt == "auto" else repr(dt)
    end_steps = -(-steps(end) // frames) * frames  # a whole number of frames: the last at the end
    return f"""# The method paper's §4.2 fixed bed, written by experiments/fixed_bed/fixed_bed.py.
time: {{step: {step_text}, end: {end_steps * (dt if dt != "auto" else 1e-5):.9g}}}
seed: {seed}
skin: {SKIN}

materials:
  # The paper gives no material. A ceramic catalyst's density; a stiffness softened for DEM
  # (the volume law's step grows as 1/sqrt(E)) but stiff enough for landings at 6 m/s
  # (experiments/fixed_bed/README.md, "Stiffness"); friction and restitution of a rough ceramic.
  catalyst: {{density: 1800, youngs_modulus: {youngs:.6g}, poisson_ratio: 0.3, friction: 0.5,
              restitution: 0.3}}
  tube: {{density: 7800, youngs_modulus: {youngs:.6g}, poisson_ratio: 0.3, friction: 0.3,
          restitution: 0.3}}

templates:
  pellet: {{shape: "{pellet_spec(sides)}", material: catalyst}}

particles:
  - feed:
      template: pellet
      region: {{cylinder: {{base: [0, 0, {feed_base:.6g}], axis: [0, 0, 1], radius: {feed_radius:.6g},
                           height: {size['feed_height']:.6g}}}}}
      rate: {rate:.6g}
      stop: {stop:.6g}
      velocity: [0, 0, -2]
      random_orientation: true

walls:
  - cylinder: {{name: tube, base: [0, 0, 0], axis: [0, 0, 1], radius: {radius:.6g}, height: {top:.6g},
               bottom_cap: true, segments: {TUBE_SEGMENTS}, material: tube}}

effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true

outputs:
  trajectories: {{every: {frames}, directory: frames, format: csv}}
  vtk: {{every: {end_steps}, directory: vtk}}
  probes: {{every: {steps(0.01)}, file: probes.csv, quantities: [kinetic_energy, bed_height]}}
  # A run longer than a sitting (the GPU machine's calls are 10 minutes) stops with a checkpoint
  # at SIGTERM (--time-limit) and continues from it (--continue).
  checkpoint: {{every: {frames * 5}, directory: checkpoints, keep: 1}}
"""


def advised_step(talus, sides, seed, pellets, size, youngs):
    """What `step: auto` takes for this scene (0.2 of the critical step talus estimates), from a
    run of one step of it on the host: the advisor depends on the templates, materials, walls,
    gravity and the feed's speed, so the step is the full run's."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "advice.yaml")
        with open(path, "w") as f:
            f.write(scene_text(sides, seed, pellets, size, "auto", youngs))
        out = subprocess.run([talus, "run", path, "--backend", "cpu", "--threads", "1", "--quiet",
                              "--end", "1e-4", "--output", os.path.join(tmp, "run")],
                             capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit(f"fixed_bed.py: {talus} could not give the time-step advice:\n{out.stderr}")
        summary = json.loads(out.stdout)
        return float(summary["time_step"]), float(summary["critical_time_step"])


# ---------------------------------------------------------------------------------------------
# The analysis


def cap_axis(shape_json):
    """The pellet's axis in its body frame: the normal of its caps, the faces with the most
    corners (N-gons; the sides are rectangles)."""
    faces = shape_json["faces"]
    cap = max(faces, key=lambda f: len(f["loop"]))
    return np.array(cap["normal"], dtype=float)


def frame_files(run_dir):
    files = glob.glob(os.path.join(run_dir, "frames", "trajectory_*.csv"))
    return sorted(files, key=lambda f: int(re.search(r"trajectory_(\d+)\.csv$", f).group(1)))


def tops_of(pos, rot, vertices):
    """Each pellet's highest posed vertex."""
    return pos[:, 2] + (rot[:, 2, :] @ vertices.T).max(axis=1)


def bed_surface(pos, rot, vel, vertices, rest_speed=0.05):
    """The bed's height: the mean of the 5 highest pellet tops among the pellets at rest (speed
    below `rest_speed`), so that pellets still falling or bouncing are not taken for the bed; the
    narrow tube holds about 5 pellets across, so the 5 highest are the top layer."""
    resting = np.linalg.norm(vel, axis=1) < rest_speed
    if not np.any(resting):
        return 0.0
    tops = np.sort(tops_of(pos[resting], rot[resting], vertices))
    return float(tops[-5:].mean())


def read_frame_full(path):
    """beds.read_frame's arrays and the velocities (n, 3), the file read once."""
    data = np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True))
    tids, pos, rot = beds.frame_arrays(data)
    return tids, pos, rot, np.stack([data["vx"], data["vy"], data["vz"]], axis=1)


def filling_record(path, vertices):
    """A frame's line of the filling: its step, pellets, pellets at rest and bed surface; and
    the frame's arrays."""
    tids, pos, rot, vel = read_frame_full(path)
    step = int(re.search(r"trajectory_(\d+)\.csv$", path).group(1))
    resting = int((np.linalg.norm(vel, axis=1) < 0.05).sum()) if len(pos) else 0
    record = {"step": step, "pellets": int(len(pos)), "resting": resting,
              "bed_height_m": bed_surface(pos, rot, vel, vertices) if len(pos) else 0.0}
    return record, (tids, pos, rot, vel)


def read_digest(out):
    """OUTPUT/filling.json's lines by step (digest_frames); empty where there is none."""
    path = os.path.join(out, "filling.json")
    return {r["step"]: r for r in json.load(open(path))} if os.path.exists(path) else {}


def digest_frames(out, talus, sides, prune):
    """Adds the filling's line of every frame in OUTPUT/run/frames to OUTPUT/filling.json (by
    step; a frame written again by a resumed run gives the same line); with `prune`, then
    removes every frame but the newest. A run that outgrows the disk or a call's transfer thus
    keeps its height curve in a few kilobytes, and OUTPUT (its checkpoint, filling.json, the
    newest frame) can go on on another machine."""
    run_dir = os.path.join(out, "run")
    files = frame_files(run_dir)
    digest = read_digest(out)
    if not files:
        return digest
    shape = beds.shape_data(talus, pellet_spec(sides), os.path.join(run_dir, "shapes"))
    for f in files:
        record, _ = filling_record(f, shape["vertices"])
        digest[record["step"]] = record
    write_atomically(os.path.join(out, "filling.json"),
                     json.dumps([digest[k] for k in sorted(digest)], indent=1) + "\n")
    if prune:
        for f in files[:-1]:
            os.unlink(f)
    return digest


def binned_porosity(inside, coordinate, edges):
    """The porosity of the points in each bin of `coordinate` between consecutive `edges`
    (`inside`: whether each point lies in a pellet): per bin its middle (`mid`), porosity, binomial
    error (one sigma) and points."""
    bins = len(edges) - 1
    index = np.minimum(np.searchsorted(edges, coordinate, side="right") - 1, bins - 1)
    out = []
    for k in range(bins):
        mine = index == k
        n = int(mine.sum())
        f = float(inside[mine].mean()) if n else float("nan")
        out.append({"mid": 0.5 * (edges[k] + edges[k + 1]), "porosity": 1 - f,
                    "error": math.sqrt(f * (1 - f) / n) if n else float("nan"), "points": n})
    return out


def analyse(run_dir, talus, sides, points, seed, rings=25, digest=None):
    """Every number of the bed from the run's frames (module docstring); `digest`: the filling's
    lines of frames no longer there (digest_frames), by step."""
    spec = pellet_spec(sides)
    shape = beds.shape_data(talus, spec, os.path.join(run_dir, "shapes"))
    shape_json = json.load(open(glob.glob(os.path.join(run_dir, "shapes", "*.json"))[0]))
    axis_body = cap_axis(shape_json)
    radius = PAPER["tube_diameter_m"] / 2
    d = PAPER["pellet_diameter_m"]
    files = frame_files(run_dir)
    if not files:
        sys.exit(f"fixed_bed.py: no frames in {run_dir}/frames")
    # The bed height as the pellets land: each frame's count, pellets at rest and surface (the
    # frames present, and the digest's lines of those pruned).
    lines = dict(digest or {})
    for path in files:
        record, arrays = filling_record(path, shape["vertices"])
        lines[record["step"]] = record
    filling = [lines[k] for k in sorted(lines)]
    tids, pos, rot, vel = arrays  # the last frame's
    shapes = {t: shape for t in set(tids)}
    surface = filling[-1]["bed_height_m"]
    rng = np.random.default_rng(seed)
    # A check of the frames, quaternions and face planes: points in the whole tube up to the
    # highest pellet must find the pellets' summed volume (less the contacts' overlaps, a small
    # fraction of a percent at this stiffness), within the sampling error.
    height = float(tops_of(pos, rot, shape["vertices"]).max()) if len(pos) else 0.0
    if len(pos):
        rc = radius * np.sqrt(rng.random(points))
        ac = 2 * math.pi * rng.random(points)
        pc = np.stack([rc * np.cos(ac), rc * np.sin(ac), height * rng.random(points)], axis=1)
        f = float(beds.inside_mask(pc, tids, pos, rot, shapes).mean())
        sampled = f * math.pi * radius ** 2 * height
        summed = len(pos) * shape["volume"]
        result_check = {"found_over_summed": sampled / summed,
                        "error": math.sqrt(f * (1 - f) / points) / f if f > 0 else math.inf}
    else:
        result_check = None
    # The core: 2 pellet diameters above the floor, 2 below the surface (the ends' own structure
    # left out, as narrow-tube studies do), the whole cross-section.
    z_lo, z_hi = 2 * d, surface - 2 * d
    result = {"pellets": int(len(pos)), "surface_m": surface, "core_z_m": [z_lo, z_hi],
              "points": points, "volume_check": result_check}
    if z_hi <= z_lo:
        result["note"] = "the bed is too shallow for a core 2 diameters from each end"
        return result, filling
    # Uniform points in the core cylinder: r = R sqrt(u) makes them uniform in area.
    r = radius * np.sqrt(rng.random(points))
    phi_angle = 2 * math.pi * rng.random(points)
    z = z_lo + (z_hi - z_lo) * rng.random(points)
    pts = np.stack([r * np.cos(phi_angle), r * np.sin(phi_angle), z], axis=1)
    inside = beds.inside_mask(pts, tids, pos, rot, shapes)
    solid = float(inside.mean())
    result["porosity"] = 1 - solid
    result["porosity_error"] = math.sqrt(solid * (1 - solid) / points)  # binomial, one sigma
    # Rings of equal area from the axis to the wall: each holds points / rings on average.
    profile = binned_porosity(inside, r, radius * np.sqrt(np.linspace(0, 1, rings + 1)))
    for ring in profile:
        ring["r_m"] = ring.pop("mid")
        ring["from_wall_d"] = (radius - ring["r_m"]) / d
    result["radial_profile"] = profile
    # Orientations of the pellets in the core: |cos| of the angle between each pellet's axis and
    # the tube's; random orientations give |cos| uniform on [0, 1] (mean 0.5).
    core = (pos[:, 2] > z_lo) & (pos[:, 2] < z_hi)
    axes = rot[core] @ axis_body
    cos = np.abs(axes[:, 2])
    hist, bins = np.histogram(cos, bins=10, range=(0, 1))
    result["orientation"] = {"pellets": int(core.sum()), "mean_abs_cos": float(cos.mean()),
                             "histogram": hist.tolist(), "bins": bins.tolist()}
    # Along the bed: the core's points in slabs of at least 2 pellet diameters (at most 20). The
    # pellets at the bottom fell 1.8 m, those at the top about 0.5 m, and a landing's speed
    # compacts the bed (README, "Stiffness"), so the porosity may change with the height.
    slabs = max(1, min(20, int((z_hi - z_lo) / (2 * d))))
    axial = binned_porosity(inside, z, np.linspace(z_lo, z_hi, slabs + 1))
    for slab in axial:
        slab["z_m"] = slab.pop("mid")
    result["axial_profile"] = axial
    return result, filling


# ---------------------------------------------------------------------------------------------
# Outputs


def figure(result, filling, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.6))
    ax = axes[0]
    prof = result.get("radial_profile", [])
    if prof:
        x = [p["from_wall_d"] for p in prof]
        ax.errorbar(x, [p["porosity"] for p in prof], yerr=[p["error"] for p in prof], fmt="o-",
                    ms=3)
        ax.axhline(result["porosity"], color="0.5", ls="--",
                   label=f"mean {result['porosity']:.3f} ± {result['porosity_error']:.3f}")
        ax.legend()
    ax.set_xlabel("distance from the wall (pellet diameters)")
    ax.set_ylabel("porosity of the ring")
    ax.set_title("(a) radial porosity profile")
    ax = axes[1]
    o = result.get("orientation")
    if o:
        centres = 0.5 * (np.array(o["bins"][:-1]) + np.array(o["bins"][1:]))
        total = sum(o["histogram"])
        ax.bar(centres, np.array(o["histogram"]) / max(total, 1), width=0.09,
               label=f"{o['pellets']} pellets, mean {o['mean_abs_cos']:.3f}")
        ax.axhline(0.1, color="0.5", ls="--", label="random orientations (0.1 a bin)")
        ax.legend()
    ax.set_xlabel("|cos| of the angle between the pellet's axis and the tube's")
    ax.set_ylabel("fraction of the core's pellets")
    ax.set_title("(b) orientations")
    ax = axes[2]
    ax.plot([f["resting"] for f in filling], [f["bed_height_m"] for f in filling], "o-", ms=3)
    ax.set_xlabel("pellets at rest in the tube (each frame)")
    ax.set_ylabel("bed height, m (pellets at rest)")
    ax.set_title("(c) bed height as the pellets land")
    ax = axes[3]
    ax_prof = result.get("axial_profile", [])
    if ax_prof:
        ax.errorbar([p["porosity"] for p in ax_prof], [p["z_m"] for p in ax_prof],
                    xerr=[p["error"] for p in ax_prof], fmt="o-", ms=3)
    ax.set_xlabel("porosity of the slab")
    ax.set_ylabel("height in the tube, m")
    ax.set_title("(d) porosity along the bed")
    fig.suptitle(title)
    fig.tight_layout()
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".bed.", suffix=".png")
    os.close(fd)
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def markdown(bed):
    r = bed["result"]
    lines = ["# Fixed bed (method paper §4.2): results", "",
             f"talus commit `{bed['commit']}`, {bed['machine']}; pellets `{bed['pellet']}`, "
             f"seed {bed['seed']}, E = {bed.get('youngs_modulus_pa', 1e6):.0e} Pa, "
             f"time step {bed['time_step_s']:.3g} s "
             f"({bed['time_step_s'] / bed['critical_time_step_s']:.2f} of the critical step); "
             f"run {bed['run_wall_seconds']:.0f} s. Command:", "", "    " + bed["command"], "",
             "| quantity | value |", "|---|---|",
             f"| pellets in the tube | {r['pellets']} of {bed['pellets_fed']} fed"
             + ("" if r["pellets"] == bed["pellets_fed"] else " (the feed fell behind: the run "
                "ended before every pellet went in)") + " |",
             f"| bed height (top layer at rest) | {r['surface_m']:.4f} m |"]
    if "porosity" in r:
        lines += [f"| mean porosity, {r['core_z_m'][0]:.4f} to {r['core_z_m'][1]:.4f} m | "
                  f"{r['porosity']:.4f} ± {r['porosity_error']:.4f} ({r['points']} points) |",
                  f"| mean \\|cos\\| of the pellets' axes to the tube's | "
                  f"{r['orientation']['mean_abs_cos']:.3f} (random: 0.5) |",
                  "", "Radial profile (rings of equal area, from the axis to the wall):", "",
                  "| r, mm | from the wall, d_p | porosity | ± |", "|---|---|---|---|"]
        lines += [f"| {1e3 * p['r_m']:.2f} | {p['from_wall_d']:.3f} | {p['porosity']:.4f} | "
                  f"{p['error']:.4f} |" for p in r["radial_profile"]]
        lines += ["", "Along the bed (slabs of the core, from the bottom):", "",
                  "| z, m | porosity | ± |", "|---|---|---|"]
        lines += [f"| {p['z_m']:.4f} | {p['porosity']:.4f} | {p['error']:.4f} |"
                  for p in r.get("axial_profile", [])]
    else:
        lines += ["", r.get("note", "")]
    return "\n".join(lines) + "\n"


def run_talus(argv, info, info_path, time_limit):
    """Runs talus (a start or a resume) for at most `time_limit` seconds (sittings.py); returns
    whether the run has ended."""
    summary = run_sitting(argv, info, info_path, time_limit, "fixed_bed.py")
    if summary is None:
        print(f"fixed_bed.py: continue with --continue {os.path.dirname(info_path)}")
        return False
    info.update(backend=summary.get("backend"), steps=summary.get("steps"),
                particles=summary.get("particles"))
    write_atomically(info_path, json.dumps(info, indent=2) + "\n")
    return True


def git_commit():
    try:
        return subprocess.run(["git", "-C", REPO, "rev-parse", "--short=12", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--talus", default=os.path.join(REPO, "build", "talus"))
    p.add_argument("--sides", type=int, default=16, help="the pellets' prism sides (default 16)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--pellets", type=int, default=None,
                   help="pellets fed (default: those that fill the tube to the paper's 1.26 m "
                        "at a solid fraction of 0.59, 2866 of 16 sides; --quick 60)")
    p.add_argument("--youngs-modulus", type=float, default=None, metavar="PA",
                   help="the pellets' and the tube's Young's modulus (default 1e8; --quick 1e6)")
    p.add_argument("--backend", choices=("auto", "cpu", "cuda"), default="auto")
    p.add_argument("--threads", type=int, default=0, help="host threads (default: OpenMP's)")
    p.add_argument("--points", type=int, default=400000, help="random points of the analysis")
    p.add_argument("--output", default="scratch/fixed_bed")
    p.add_argument("--quick", action="store_true", help="CI's size: a 0.12 m tube, 60 pellets")
    p.add_argument("--analyse", metavar="RUN_DIR", default=None,
                   help="only analyse an earlier run's folder (its run/ and scene.yaml)")
    p.add_argument("--continue", dest="resume", metavar="OUTPUT", default=None,
                   help="resume an earlier call's run that --time-limit stopped, then analyse")
    p.add_argument("--time-limit", type=float, default=None, metavar="S",
                   help="stop talus after S seconds with a checkpoint (exit status 3)")
    p.add_argument("--commit", default=None)
    p.add_argument("--prune-frames", action="store_true",
                   help="after each sitting, keep each frame's filling line in filling.json and "
                        "remove every frame but the newest (a run carried between machines)")
    a = p.parse_args(argv)
    if a.sides < 3 or a.points < 1000:
        p.error("--sides must be at least 3 and --points at least 1000")
    if a.youngs_modulus is not None and not a.youngs_modulus > 0:
        p.error(f"--youngs-modulus {a.youngs_modulus}: expected a positive modulus in Pa")
    size = QUICK if a.quick else FULL
    pellets = a.pellets or size["pellets"] or paper_bed_pellets(a.sides)
    youngs = a.youngs_modulus or size["youngs"]
    out = a.analyse or a.resume or a.output
    os.makedirs(out, exist_ok=True)
    run_dir = os.path.join(out, "run")
    info_path = os.path.join(out, "run.json")
    digest = None  # the filling's lines of pruned frames (digest_frames)
    if a.analyse:
        info = json.load(open(info_path))
        if not info.get("finished"):
            sys.exit(f"fixed_bed.py: the run in {run_dir} has not ended; --continue it first")
    elif not a.resume:
        dt, crit = advised_step(a.talus, a.sides, a.seed, pellets, size, youngs)
        scene = os.path.join(out, "scene.yaml")
        write_atomically(scene, scene_text(a.sides, a.seed, pellets, size, dt, youngs))
        argv_run = [a.talus, "run", scene, "--backend", a.backend, "--quiet", "--output",
                    run_dir, "--overwrite"]
        if a.threads:
            argv_run += ["--threads", str(a.threads)]
        info = {"time_step_s": dt, "critical_time_step_s": crit, "run_wall_seconds": 0.0,
                "run_command": " ".join(argv_run), "sides": a.sides, "seed": a.seed,
                "pellets_fed": pellets, "quick": a.quick,
                "youngs_modulus_pa": youngs, "sittings": 0}
        ended = run_talus(argv_run, info, info_path, a.time_limit)
        digest = digest_frames(out, a.talus, info["sides"], a.prune_frames)
        if not ended:
            return 3
    elif a.resume:
        info = json.load(open(info_path))
        if not info.get("finished"):
            argv_run = [a.talus, "run", "--resume", os.path.join(run_dir, "checkpoints"),
                        "--quiet"] + (["--threads", str(a.threads)] if a.threads else [])
            ended = run_talus(argv_run, info, info_path, a.time_limit)
            digest = digest_frames(out, a.talus, info["sides"], a.prune_frames)
            if not ended:
                return 3
    if digest is None:  # --analyse, or --continue of a run that had ended
        digest = read_digest(out)
    result, filling = analyse(run_dir, a.talus, info["sides"], a.points, info["seed"],
                              digest=digest)
    bed = dict(info, result=result, filling=filling, paper=PAPER,
               pellet=pellet_spec(info["sides"]), commit=a.commit or git_commit(),
               machine=f"{platform.node()} ({platform.machine()}, {os.cpu_count()} CPUs)",
               command=" ".join([sys.executable] + sys.argv))
    write_atomically(os.path.join(out, "bed.json"), json.dumps(bed, indent=2) + "\n")
    write_atomically(os.path.join(out, "bed.md"), markdown(bed))
    figure(result, filling, os.path.join(out, "bed.png"),
           f"Fixed bed: {info['pellets_fed']} pellets ({pellet_spec(info['sides'])}) in a "
           f"{PAPER['tube_diameter_m'] * 1e3:.0f} mm tube")
    print(json.dumps({k: result[k] for k in ("pellets", "surface_m", "porosity",
                                             "porosity_error") if k in result}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
