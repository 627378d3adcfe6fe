#!/usr/bin/python3
"""HDF5 trajectory frames read back by h5py, a reader that shares no code with talus.

Runs one small scene through `talus run` twice, with `outputs.trajectories.format: hdf5` and
`csv` (the host backend on one thread: the two runs are the same bits), and loads each HDF5 frame
in one call, `h5py.File(path)["particles"][:]`, as a numpy structured array. Checks against the
CSV frame of the same step: the same frames, ids and templates; positions to the bit; the
orientation and velocities rounded to float32 (docs/scenes.md, "Output files"); the attributes
step and time; run.json's trajectory_format.

Usage: hdf5_readback.py TALUS WORK_DIR. Exit status 77 (ctest's SKIP_RETURN_CODE) when h5py or
numpy cannot be imported; scripts/setup installs python3-h5py.
"""

import csv
import glob
import json
import os
import re
import shutil
import subprocess
import sys

try:
    import h5py
    import numpy
except ImportError as error:
    print(f"SKIPPED: h5py or numpy is not importable by {sys.executable} ({error}); install "
          "Debian's python3-h5py (scripts/setup does)")
    sys.exit(77)

TIME_STEP, EVERY = 5.0e-5, 40  # 120 steps: frames 0, 40, 80 and 120

SCENE = f"""time: {{step: {TIME_STEP}, end: 0.006}}
materials:
  glass: {{density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}}
templates:
  grain: {{shape: "dodecahedron:0.01", material: glass}}
  block: {{shape: "cuboid:0.012,0.008,0.006", material: glass}}
particles:
  - lattice: {{template: grain, region: {{box: {{min: [-0.025, -0.025, 0.01],
              max: [0.025, 0.025, 0.035]}}}}, spacing: 0.012, random_orientation: true, seed: 5}}
  - explicit:
      - {{template: block, position: [0, 0, 0.05], velocity: [0.1, 0, 0],
         angular_velocity: [3, -2, 7]}}
walls:
  - box: {{min: [-0.04, -0.04, 0], max: [0.04, 0.04, 0.08], open_top: true, material: glass}}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
outputs:
  trajectories: {{every: {EVERY}, directory: frames, format: FORMAT}}
"""


def main():
    talus, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)

    for fmt in ("hdf5", "csv"):
        os.makedirs(os.path.join(work, fmt))
        path = os.path.join(work, fmt, "scene.yaml")
        with open(path, "w") as f:
            f.write(SCENE.replace("FORMAT", fmt))
        result = subprocess.run([talus, "run", path, "--backend", "cpu", "--threads", "1",
                                 "--quiet", "--output", os.path.join(work, fmt)],
                                capture_output=True, text=True)
        if result.returncode != 0:
            print(f"talus run ({fmt}) failed with {result.returncode}:\n{result.stderr}")
            return 1
        with open(os.path.join(work, fmt, "frames", "run.json")) as f:
            check(json.load(f)["trajectory_format"] == fmt, f"run.json: trajectory_format {fmt}")

    h5_files = sorted(glob.glob(os.path.join(work, "hdf5", "frames", "trajectory_*.h5")))
    csv_files = sorted(glob.glob(os.path.join(work, "csv", "frames", "trajectory_*.csv")))
    steps = [int(re.search(r"_(\d+)\.h5$", p).group(1)) for p in h5_files]
    check(steps == [0, 40, 80, 120], f"HDF5 frames at steps {steps}, expected 0, 40, 80, 120")
    check(len(csv_files) == len(h5_files), "as many CSV frames as HDF5 frames")
    for h5_path, csv_path in zip(h5_files, csv_files):
        name = os.path.basename(h5_path)
        with h5py.File(h5_path, "r") as f:
            dataset = f["particles"]
            particles = dataset[:]  # the whole frame, one call
            step, time = int(dataset.attrs["step"]), float(dataset.attrs["time"])
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
        check(len(particles) == len(rows) >= 10, f"{name}: {len(particles)} particles, "
              f"{len(rows)} CSV rows, expected the same and at least 10")
        check(step == int(re.search(r"_(\d+)\.h5$", h5_path).group(1)), f"{name}: step {step}")
        check(abs(time - step * TIME_STEP) <= 1e-12, f"{name}: time {time}")
        for p, row in zip(particles, rows):
            where = f"{name}: particle {row['id']}"
            check(int(p["id"]) == int(row["id"]) and int(p["template"]) == int(row["template"]),
                  f"{where}: id or template")
            position = [float(row[k]) for k in ("x", "y", "z")]
            check(list(p["position"]) == position, f"{where}: position {list(p['position'])} "
                  f"against {position} (exact)")
            for field, keys in (("orientation", ("qw", "qx", "qy", "qz")),
                                ("velocity", ("vx", "vy", "vz")),
                                ("angular_velocity", ("wx", "wy", "wz"))):
                expected = numpy.array([float(row[k]) for k in keys], dtype=numpy.float32)
                check(numpy.array_equal(p[field], expected),
                      f"{where}: {field} {p[field]} against {expected} (float32)")
    if failures:
        print("\n".join(failures[:20]))
        print(f"{len(failures)} failure(s)")
        return 1
    print(f"hdf5_readback: {len(h5_files)} frames of {len(rows)} particles match the CSV frames")
    return 0


if __name__ == "__main__":
    sys.exit(main())
