#!/usr/bin/python3
"""ctest `silo_quick`: the §4.1 silo driver end to end at CI's size (silo.py --quick: the
corrugated silo at 0.08 of the paper's size, 20 mineral particles fed from its top, on the host),
stopped with a checkpoint after 2 s and continued (--time-limit, --continue), its silo.json and
wall mesh checked.

    test_quick.py TALUS WORK_DIR

Checks, each a number that a broken mesh, scene or analysis gets wrong:
  - the mesh has the triangles its construction gives (the outlet's disk of 96, two a side for
    each of the 6 hopper rings and the bin's rows: 8 a pitch), every one wound with its normal
    into the silo (up for the disk, towards the axis for the walls: a flipped facet would push
    particles out through it);
  - every particle fed is in the silo at the end, none outside the corrugated wall, all in the
    hopper's lower part (20 particles fill less than the hopper);
  - the run took two sittings and ran every step of the scene's time;
  - the wall stage's share of the step lies in (0, 1) and the particles at the wall have facets
    within reach (at least 10 each on average: a 96-sided wall of 8 rows a pitch puts dozens
    within a bounding diameter);
  - silo.md and silo.png are written.
Skipped (77) without /usr/bin/python3's numpy and matplotlib.
"""
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def main(argv):
    if len(argv) != 2:
        print("usage: test_quick.py TALUS WORK_DIR", file=sys.stderr)
        return 2
    talus, work = argv
    for module in ("numpy", "matplotlib"):
        if importlib.util.find_spec(module) is None:
            print(f"SKIPPED: {sys.executable} has no {module} (Debian's python3-{module})")
            return 77
    import numpy as np
    shutil.rmtree(work, ignore_errors=True)
    # Stopped after 2 s (the run takes 15 s or more here), then continued: the path a GPU run
    # longer than a call takes.
    driver = [sys.executable, os.path.join(HERE, "silo.py")]
    proc = subprocess.run(driver + ["--talus", talus, "--quick", "--threads", "1", "--output",
                                    work, "--time-limit", "2"], capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 3:
        print(f"silo.py --quick --time-limit 2 exited with {proc.returncode}, expected 3 "
              "(stopped with a checkpoint)")
        return 1
    proc = subprocess.run(driver + ["--continue", work], capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 0:
        print(f"silo.py --continue exited with {proc.returncode}")
        return 1
    info = json.load(open(os.path.join(work, "silo.json")))
    r, dims, geo = info["result"], info["dimensions"], info["geometry"]
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    # The mesh as read back from the file.
    vertices, tris = [], []
    for line in open(os.path.join(work, "silo.obj")):
        if line.startswith("v "):
            vertices.append([float(v) for v in line.split()[1:4]])
        elif line.startswith("f "):
            tris.append([int(v) - 1 for v in line.split()[1:4]])
    vertices, tris = np.array(vertices), np.array(tris)
    n = geo["segments"]
    rows = round((dims["height"] - dims["hopper_height"]) / geo["pitch_m"] * geo["rows_per_pitch"])
    expected = n + 2 * n * (6 + rows)
    check(len(tris) == expected == info["facets"],
          f"{len(tris)} triangles in silo.obj, silo.json says {info['facets']}, "
          f"expected {expected}")
    p = vertices[tris]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    centre = p.mean(axis=1)
    disk = np.arange(len(tris)) < n
    up = normal[disk, 2] > 0
    inward = (normal[~disk, 0] * -centre[~disk, 0] + normal[~disk, 1] * -centre[~disk, 1]) > 0
    check(up.all() and inward.all(), f"{int((~up).sum())} disk and {int((~inward).sum())} wall "
          "triangles face out of the silo")
    check(r["particles"] == info["particles_fed"] == 20,
          f"{r['particles']} particles at the end, fed {info['particles_fed']}, expected 20")
    check(r["outside"] == 0, f"{r['outside']} particles outside the corrugated wall")
    check(0 < r["lowest_z_m"] and r["highest_z_m"] < dims["hopper_height"],
          f"particles from z = {r['lowest_z_m']:.4f} to {r['highest_z_m']:.4f} m, expected "
          f"within the hopper (0 to {dims['hopper_height']:.4f} m)")
    # Every step of the scene's time run, over the two sittings: a resume that restarted from
    # step 0, or stopped early, gives another count.
    run = info["run"]
    fall = math.sqrt(2 * dims["height"] / 9.81)
    steps = (info["feed_seconds"] + fall + info["settle_seconds"]) / run["time_step_s"]
    check(run["sittings"] == 2 and abs(run["steps"] - steps) <= 1,
          f"{run['steps']} steps in {run['sittings']} sittings, expected {steps:.0f} in 2")
    share = run["wall_share"]
    check(0 < share < 1, f"the wall stage's share {share}")
    near = r.get("facets_near_wall_particles", {}).get("mean", 0)
    check(near >= 10, f"{near} facets within reach of a wall particle on average")
    for name in ("silo.md", "silo.png"):
        path = os.path.join(work, name)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"{name}: not written")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print(f"silo_quick: {len(tris)} facets, {r['particles']} particles, wall stage "
              f"{100 * share:.1f} %, {near:.0f} facets near a wall particle; "
              f"{math.ceil(info['run']['wall_seconds'])} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
