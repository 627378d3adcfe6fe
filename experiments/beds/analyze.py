#!/usr/bin/env python3
"""Turns the poured-bed runs of run_beds.sh into a figure and two tables.

    analyze.py OUT [--talus BIN] [--points 200000] [--rest-fraction 1e-4]

Reads OUT/runs.csv (exit status, wall time), each OUT/runs/<case>/{probes.csv, summary.json,
stderr.log, frames/} and the scenes in OUT/scenes*/, and writes into OUT:

  kinetic_energy.png  kinetic energy against time, log scale, one curve per case
  beds.csv, beds.md   per case: time to rest, final kinetic energy, the fraction of the released
                      energy left, energy created by the contacts, whether the run stopped early,
                      the packing fraction in the core of the bed and its sampling error

The packing fraction is measured on the true polyhedra: random points in a core box, each tested
against the face planes of the posed particles near it. The body-frame face planes come from
`talus shape SPEC` (cached in OUT/shapes/). Needs numpy and matplotlib.
"""

import argparse
import csv
import glob
import json
import math
import os
import re
import subprocess
import sys

import numpy as np

G = 9.81  # m/s^2, the scenes' |gravity|


# ---------------------------------------------------------------------------------------------
# Reading the runs


def read_probes(path):
    """The probe columns as numpy arrays by name; None when the file is missing or empty."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return None
    header, body = rows[0], rows[1:]
    # A run killed mid-write can leave a short last line; keep only whole rows.
    body = [r for r in body if len(r) == len(header)]
    data = np.array(body, dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def read_scene(path):
    """What the analysis needs from a scene written by make_scenes.py: template specs, density,
    the box wall, the contact law. A few regular expressions suffice for those generated files."""
    text = open(path).read()
    box = re.search(r"box: \{name: box, min: \[([^\]]*)\], max: \[([^\]]*)\]", text)
    return {
        "templates": dict(re.findall(r"^  (\w+): \{shape: \"([^\"]+)\"", text, re.M)),
        "density": float(re.search(r"density: ([0-9.eE+-]+)", text).group(1)),
        "box_min": np.array([float(v) for v in box.group(1).split(",")]),
        "box_max": np.array([float(v) for v in box.group(2).split(",")]),
        "law": re.search(r"^  contact: (\w+)", text, re.M).group(1),
    }


def shape_data(talus, spec, cache_dir):
    """The template in its body frame (`talus shape`): volume, bounding radius, vertices, face
    planes (outward unit normal n and offset o: inside where n . x <= o for every face)."""
    os.makedirs(cache_dir, exist_ok=True)
    path = os.path.join(cache_dir, re.sub(r"[^A-Za-z0-9._-]", "_", spec) + ".json")
    if not os.path.exists(path):
        if not talus:
            sys.exit(f"analyze.py: no cached shape for '{spec}' in {cache_dir}; pass --talus BIN")
        text = subprocess.run([talus, "shape", spec], check=True, capture_output=True,
                              text=True).stdout
        with open(path, "w") as f:
            f.write(text)
    shape = json.load(open(path))
    return {
        "volume": shape["volume"],
        "radius": shape["bounding_radius"],
        "vertices": np.array(shape["vertices"]),
        "normals": np.array([face["normal"] for face in shape["faces"]]),
        "offsets": np.array([face["offset"] for face in shape["faces"]]),
    }


def read_frame(path):
    """A trajectory frame: template ids, centroids (n, 3), body-to-world rotations (n, 3, 3)."""
    return frame_arrays(np.atleast_1d(np.genfromtxt(path, delimiter=",", names=True)))


def frame_arrays(data):
    """read_frame's arrays from a frame's columns as numpy reads them (named fields)."""
    pos = np.stack([data["x"], data["y"], data["z"]], axis=1)
    q = np.stack([data["qw"], data["qx"], data["qy"], data["qz"]], axis=1)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    rot = np.empty((len(q), 3, 3))
    rot[:, 0] = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], 1)
    rot[:, 1] = np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], 1)
    rot[:, 2] = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1)
    return data["template"].astype(int), pos, rot


def frames_of(run_dir):
    """The trajectory frames by step, and the run's template names by id."""
    files = glob.glob(os.path.join(run_dir, "frames", "trajectory_*.csv"))
    frames = {int(re.search(r"trajectory_(\d+)\.csv$", f).group(1)): f for f in files}
    info_path = os.path.join(run_dir, "frames", "run.json")
    names = {}
    if os.path.exists(info_path):
        names = {t["id"]: t["name"] for t in json.load(open(info_path))["templates"]}
    return frames, names


# ---------------------------------------------------------------------------------------------
# Packing fraction


def inside_mask(points, tids, pos, rot, shapes):
    """Which points lie inside any of the posed polyhedra (closed: on a face counts as inside).

    Points are bucketed in a grid of cells no smaller than a bounding diameter, so each particle
    meets only the points of the at most 2 x 2 x 2 cells its bounding sphere touches; the points
    within its bounding sphere are then taken to its body frame and tested against its faces.
    """
    inside = np.zeros(len(points), dtype=bool)
    if len(points) == 0:
        return inside
    cell = 2 * max(s["radius"] for s in shapes.values())
    lo = points.min(axis=0)
    dims = np.floor((points.max(axis=0) - lo) / cell).astype(int) + 1
    ijk = np.floor((points - lo) / cell).astype(int)
    keys = (ijk[:, 0] * dims[1] + ijk[:, 1]) * dims[2] + ijk[:, 2]
    order = np.argsort(keys, kind="stable")
    starts = np.searchsorted(keys[order], np.arange(dims.prod() + 1))
    for t, x, r_mat in zip(tids, pos, rot):
        s = shapes[t]
        r = s["radius"]
        a = np.maximum(np.floor((x - r - lo) / cell).astype(int), 0)
        b = np.minimum(np.floor((x + r - lo) / cell).astype(int), dims - 1)
        if np.any(b < a):
            continue  # the bounding sphere misses the sampled region
        chunks = []
        for i in range(a[0], b[0] + 1):
            for j in range(a[1], b[1] + 1):
                row = (i * dims[1] + j) * dims[2]  # cells (i, j, a[2] .. b[2]) are consecutive
                chunks.append(order[starts[row + a[2]]:starts[row + b[2] + 1]])
        idx = np.concatenate(chunks)
        if idx.size == 0:
            continue
        rel = points[idx] - x
        idx = idx[np.einsum("ij,ij->i", rel, rel) <= r * r]
        if idx.size == 0:
            continue
        body = (points[idx] - x) @ r_mat  # rows: R^T (p - x)
        inside[idx[np.all(body @ s["normals"].T <= s["offsets"], axis=1)]] = True
    return inside


def surface_height(tids, pos, rot, shapes, diameter, box_min):
    """The free surface: the median over columns one diameter wide of the highest particle top.

    The probe's bed height is the single highest vertex; one particle resting on the surface, or
    still bouncing, would lift it. The median of column tops is the level of the surface itself.
    A particle's top is its highest posed vertex.
    """
    tops = np.empty(len(pos))
    for t in set(tids):
        mine = tids == t
        tops[mine] = pos[mine, 2] + (rot[mine, 2, :] @ shapes[t]["vertices"].T).max(axis=1)
    ij = np.floor((pos[:, :2] - box_min[:2]) / diameter).astype(int)
    column_top = {}
    for key, z in zip(map(tuple, ij), tops):
        column_top[key] = max(column_top.get(key, -np.inf), z)
    return float(np.median(list(column_top.values()))) if column_top else float("nan")


def core_packing(frame_path, scene, shapes_by_name, names, args):
    """Packing fraction in the core box of the final frame, with its binomial standard error."""
    tids, pos, rot = read_frame(frame_path)
    shapes = {t: shapes_by_name[names.get(t, next(iter(shapes_by_name)))] for t in set(tids)}
    d = 2 * max(s["radius"] for s in shapes.values())  # circumscribed diameter
    top = surface_height(tids, pos, rot, shapes, d, scene["box_min"])
    lo = scene["box_min"] + np.array([args.wall_inset, args.wall_inset, args.floor_inset]) * d
    hi = np.array([scene["box_max"][0] - args.wall_inset * d,
                   scene["box_max"][1] - args.wall_inset * d, top - args.surface_inset * d])
    # The core's height in diameters, negative where the bed is too shallow for one.
    result = {"surface_height": top, "core_min": lo, "core_max": hi,
              "core_height_d": float((hi[2] - lo[2]) / d),
              "phi": float("nan"), "phi_error": float("nan"), "points": 0}
    rng = np.random.default_rng(args.seed)
    if args.check_volume:
        # Sampling the box around every particle must find their summed volume (less the
        # contacts' overlaps): a check of the frames, the quaternions and the face planes.
        lo_all, hi_all = pos.min(axis=0) - d / 2, pos.max(axis=0) + d / 2
        pts = lo_all + (hi_all - lo_all) * rng.random((args.points, 3))
        f = inside_mask(pts, tids, pos, rot, shapes).mean()
        summed = sum(shapes[t]["volume"] for t in tids)
        result["volume_check"] = (f * np.prod(hi_all - lo_all) / summed,
                                  math.sqrt((1 - f) / (f * args.points)) if f > 0 else math.inf)
    if np.any(hi <= lo):
        return result  # the bed is too shallow (or the box too narrow) for a core
    points = lo + (hi - lo) * rng.random((args.points, 3))
    phi = float(inside_mask(points, tids, pos, rot, shapes).mean())
    result.update(phi=phi, phi_error=math.sqrt(phi * (1 - phi) / args.points), points=args.points)
    return result


# ---------------------------------------------------------------------------------------------
# Energies


def energy_summary(probes, rest_fraction):
    """Released potential energy, time to rest, what is left, and the energy the contacts made.

    Released: the drop of the gravitational energy from the first to the last probe row (for a
    run thrown apart, which ends higher than it started, the largest drop seen). At rest from the
    first probe time after which the kinetic energy stays below rest_fraction of it; NaN when it
    never does (the last row is above). Created: the growth of held + dissipated energy (constant
    in an exact run), over the released energy.
    """
    t, ke, grav = probes["time"], probes["kinetic_energy"], probes["gravitational"]
    released = grav[0] - grav[-1]
    if not released > 0:
        released = grav[0] - grav.min()
    above = np.nonzero(ke >= rest_fraction * released)[0]
    if len(above) == 0:
        rest = t[0]
    elif above[-1] + 1 < len(t):
        rest = t[above[-1] + 1]
    else:
        rest = float("nan")
    balance = probes.get("energy_balance")
    created = (balance[-1] - balance[0]) / released if balance is not None else float("nan")
    return {"released": released, "time_to_rest": rest, "final_ke": ke[-1],
            "ke_left": ke[-1] / released, "created": created, "end_time": t[-1]}


def stop_reason(run_dir, status):
    """Why a run ended early (the watchdog, a signal, another exit status), or ''."""
    path = os.path.join(run_dir, "stderr.log")
    text = open(path).read() if os.path.exists(path) else ""
    m = re.search(r"stopped at step (\d+) \(t = ([0-9.eE+-]+) s", text)
    if m:
        return f"watchdog at t = {float(m.group(2)):.3g} s"
    m = re.search(r"interrupted by (\w+) at step \d+ \(t = ([0-9.eE+-]+) s", text)
    if m:
        return f"{m.group(1)} at t = {float(m.group(2)):.3g} s"
    if status == "":
        # No row in runs.csv: still running, or killed with run_beds.sh.
        summary = os.path.join(run_dir, "summary.json")
        return "" if os.path.exists(summary) and os.path.getsize(summary) else "unfinished"
    return f"exit {status} (stderr.log)" if status != "0" else ""


def critical_steps(out):
    """dt_crit by case, from the cases.txt that make_scenes.py writes beside the scenes."""
    crit = {}
    for path in glob.glob(os.path.join(out, "scenes*", "cases.txt")):
        for line in open(path):
            words = line.split()
            if len(words) >= 5 and not line.startswith("#") and words[4] != "None":
                crit[words[0]] = float(words[4])
    return crit


def time_step_ratio(run_dir, dt, crit):
    """dt / dt_crit: from the run's summary, else from cases.txt, else NaN."""
    try:
        return json.load(open(os.path.join(run_dir, "summary.json")))["time_step_ratio"]
    except (OSError, ValueError, KeyError):
        return float(dt) / crit if crit else float("nan")


# ---------------------------------------------------------------------------------------------
# Output


def plot(cases, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shapes = sorted({c["shape"] for c in cases})
    colours = {s: plt.cm.tab10(i % 10) for i, s in enumerate(shapes)}
    fig, ax = plt.subplots(figsize=(10, 6.5))
    for c in cases:
        p = c["probes"]
        ke = np.where(p["kinetic_energy"] > 0, p["kinetic_energy"], np.nan)  # log scale
        style = "--" if c["law"] == "volume_paper" else (":" if c["tag"] else "-")
        label = f"{c['shape']}, {c['law']}, dt {float(c['dt']):.2g} s"
        if c["stopped"]:
            label += f" ({c['stopped']})"
        ax.semilogy(p["time"], ke, style, color=colours[c["shape"]], lw=1.4, label=label)
        if c["stopped"]:
            ax.plot(p["time"][-1], ke[-1], "x", color=colours[c["shape"]], ms=9, mew=2)
    ax.set_xlim(left=0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("kinetic energy (J), translational + rotational")
    n = sorted({c["particles"] for c in cases})
    ax.set_title(f"Poured beds of {', '.join(map(str, n))} particles: kinetic energy "
                 "(solid: default law; dashed: paper's law; dotted: advised step; x: stopped)")
    ax.title.set_fontsize(10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc="best", ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=130)


COLUMNS = ["case", "shape", "law", "dt", "dt_ratio", "particles", "exit_status", "stopped",
           "wall_seconds", "end_time", "released_pe", "time_to_rest", "final_ke", "ke_left",
           "energy_created", "bed_height", "surface_height", "core_height_d", "phi_core",
           "phi_error", "points"]


def fmt(v, spec=".3g"):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return format(v, spec) if isinstance(v, float) else str(v)


def write_tables(cases, out):
    with open(os.path.join(out, "beds.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for c in cases:
            w.writerow([fmt(c[k], ".6g") if isinstance(c[k], float) else c[k] for k in COLUMNS])
    lines = [
        "| shape | law | dt (s) | dt/dt_crit | particles | time to rest (s) | final KE (J) | "
        "KE left | energy created | stopped | core height (d) | packing fraction |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for c in cases:
        rest = fmt(c["time_to_rest"]) or f"not by {c['end_time']:.2g}"
        phi = f"{c['phi_core']:.3f} ± {c['phi_error']:.3f}" if c["points"] else "no core"
        if not c["has_final_frame"]:
            phi = "no final frame"
        lines.append(
            f"| {c['shape']} | {c['law']} | {float(c['dt']):.3g} | {fmt(c['dt_ratio'], '.2g')} | "
            f"{c['particles']} | {rest} | {fmt(c['final_ke'])} | {fmt(c['ke_left'])} | "
            f"{fmt(c['energy_created'])} | {c['stopped'] or 'no'} | "
            f"{fmt(c['core_height_d'], '.1f')} | {phi} |")
    notes = """
Time to rest: the first probe time after which the kinetic energy stays below {rest:g} of the
released potential energy (the drop of the gravitational energy, first to last probe). KE left:
final kinetic energy over the released energy. Energy created: the growth of held + dissipated
energy over the released energy (zero in an exact run; large where the contacts create energy
that damping then removes). Packing fraction: solid fraction of the true polyhedra in the core
box (inset {wall:g} d from the side walls, {floor:g} d from the floor, {surf:g} d below the free
surface, d the circumscribed diameter; surface = median over d-wide columns of the highest
particle top) from {points} random points; ± is the binomial standard error
sqrt(phi (1 - phi) / N).
"""
    a = cases[0]["args"] if cases else None
    with open(os.path.join(out, "beds.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
        if a:
            f.write(notes.format(rest=a.rest_fraction, wall=a.wall_inset, floor=a.floor_inset,
                                 surf=a.surface_inset, points=a.points))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="the output root of run_beds.sh")
    parser.add_argument("--talus", default=os.environ.get("TALUS"),
                        help="talus binary for `talus shape` (default $TALUS; not needed once "
                             "OUT/shapes/ holds the shapes)")
    parser.add_argument("--points", type=int, default=200000, help="sample points per core")
    parser.add_argument("--rest-fraction", type=float, default=1e-4,
                        help="at rest below this fraction of the released potential energy")
    parser.add_argument("--wall-inset", type=float, default=3.0, help="diameters")
    parser.add_argument("--floor-inset", type=float, default=2.0, help="diameters")
    parser.add_argument("--surface-inset", type=float, default=3.0, help="diameters")
    parser.add_argument("--seed", type=int, default=12345, help="of the sample points")
    parser.add_argument("--check-volume", action="store_true",
                        help="also sample the whole bed and print sampled / summed particle "
                             "volume (should be 1 within the sampling error)")
    args = parser.parse_args()

    runs = {}
    runs_csv = os.path.join(args.out, "runs.csv")
    if os.path.exists(runs_csv):
        for row in csv.DictReader(open(runs_csv)):
            runs[row["case"]] = row  # the last row of a case that was run again
    scenes = {os.path.splitext(os.path.basename(p))[0]: p
              for p in sorted(glob.glob(os.path.join(args.out, "scenes*", "*.yaml")))}

    crit = critical_steps(args.out)
    cases = []
    for name in sorted(scenes, key=lambda n: (n.split("_")[0], n)):
        run_dir = os.path.join(args.out, "runs", name)
        probes = read_probes(os.path.join(run_dir, "probes.csv"))
        if probes is None:
            print(f"analyze.py: {name}: no probes (not run yet?); skipped", file=sys.stderr)
            continue
        scene = read_scene(scenes[name])
        row = runs.get(name, {})
        status = row.get("exit_status", "")
        c = {"case": name, "shape": name.split("_")[0], "law": scene["law"],
             "tag": os.path.basename(os.path.dirname(scenes[name])) != "scenes",
             "dt": row.get("dt") or re.search(r"step: ([0-9.eE+-]+)",
                                              open(scenes[name]).read()).group(1),
             "particles": row.get("particles", ""), "exit_status": status,
             "wall_seconds": row.get("wall_seconds", ""), "probes": probes,
             "stopped": stop_reason(run_dir, status),
             "bed_height": probes["bed_height"][-1], "args": args}
        c["dt_ratio"] = time_step_ratio(run_dir, c["dt"], crit.get(name))
        e = energy_summary(probes, args.rest_fraction)
        c.update(released_pe=e["released"], time_to_rest=e["time_to_rest"],
                 final_ke=e["final_ke"], ke_left=e["ke_left"], energy_created=e["created"],
                 end_time=e["end_time"])
        # A run cut by run_beds.sh's time limit (SIGTERM: exit 143, its outputs kept) came to rest
        # or not in the part it ran, which is all measured; a run that stopped on its own (the
        # watchdog, an error) never came to rest.
        if status == "143" or c["stopped"].startswith("SIGTERM"):
            c["stopped"] = f"cut by the time limit at t = {e['end_time']:.3g} s"
        elif c["stopped"]:
            c["time_to_rest"] = float("nan")
        # The packing is measured on the last frame only when the run reached its end.
        frames, names = frames_of(run_dir)
        c["has_final_frame"] = status == "0" and len(frames) > 1
        c.update(surface_height=float("nan"), core_height_d=float("nan"),
                 phi_core=float("nan"), phi_error=float("nan"), points=0)
        if c["has_final_frame"]:
            shapes = {n: shape_data(args.talus, spec, os.path.join(args.out, "shapes"))
                      for n, spec in scene["templates"].items()}
            pk = core_packing(frames[max(frames)], scene, shapes, names, args)
            c.update(surface_height=pk["surface_height"], core_height_d=pk["core_height_d"],
                     phi_core=pk["phi"], phi_error=pk["phi_error"], points=pk["points"])
            if "volume_check" in pk:
                ratio, error = pk["volume_check"]
                print(f"analyze.py: {name}: sampled / summed particle volume = {ratio:.4f} "
                      f"(sampling error {error:.4f})", file=sys.stderr)
            if pk["points"] == 0:
                print(f"analyze.py: {name}: no core: the surface is at "
                      f"{pk['surface_height']:.3g} m, too low for the insets", file=sys.stderr)
        if not c["particles"]:
            c["particles"] = str(len(read_frame(frames[0])[0])) if 0 in frames else ""
        cases.append(c)

    if not cases:
        sys.exit(f"analyze.py: no runs with probes under {args.out}/runs")
    plot(cases, os.path.join(args.out, "kinetic_energy.png"))
    write_tables(cases, args.out)
    print(open(os.path.join(args.out, "beds.md")).read())
    print(f"analyze.py: wrote {args.out}/kinetic_energy.png, beds.csv, beds.md", file=sys.stderr)


if __name__ == "__main__":
    main()
