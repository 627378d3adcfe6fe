#!/usr/bin/python3
"""ParaView output read back by VTK itself.

Runs a small scene through `talus run` (the production solver on the host backend; also `auto`,
which is the CUDA backend where a GPU is usable, and the reference solver where this talus has
it) and reads the outputs.vtk files with VTK's own XML reader (Debian's python3-vtk9, so a reader
that shares no code with talus), the .pvd collections with Python's XML parser. Checks against the
scene, the trajectory CSV of the same run and `talus shape`: frames and times, point and cell
counts, each polyhedron's points = position + R(q) template vertex, spheres' points on their
sphere, cell and point data equal to the trajectory's values, the walls where their motion puts
them.

Usage: vtk_readback.py TALUS WORK_DIR. Exit status 77 (ctest's SKIP_RETURN_CODE) when VTK cannot
be imported; scripts/setup installs python3-vtk9.
"""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as error:
    print(f"SKIPPED: VTK's Python module is not importable by {sys.executable} ({error}); "
          "install Debian's python3-vtk9 (scripts/setup does)")
    sys.exit(77)

TIME_STEP, END, EVERY = 1.0e-4, 0.0175, 50  # 175 steps: frames 0, 50, 100, 150 and the last
GRAIN, CUBE, BALL_RADIUS = "dodecahedron:0.01", "cuboid:0.012,0.008,0.006", 0.004
BOX_MIN, BOX_MAX, BOX_VELOCITY = (-0.04, -0.04, 0.0), (0.04, 0.04, 0.08), (0.02, -0.01, 0.0)
# docs/scenes.md, "ParaView files": a sphere is drawn with 6 bands of 12 segments.
SPHERE_POINTS, SPHERE_FACES = 2 + 5 * 12, 6 * 12

SCENE = f"""time: {{step: {TIME_STEP}, end: {END}}}
materials:
  glass: {{density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4,
          restitution: 0.5}}
templates:
  grain: {{shape: "{GRAIN}", material: glass}}
  block: {{shape: "{CUBE}", material: glass}}
  ball: {{sphere: {BALL_RADIUS}, material: glass}}
particles:
  - explicit:
      - {{template: grain, position: [0, 0, 0.02], orientation: {{axis: [1, 2, 3], degrees: 40}},
         velocity: [0.1, 0, 0], angular_velocity: [3, -2, 7]}}
      - {{template: block, position: [0.02, 0.01, 0.012], angular_velocity: [0, 5, 1]}}
      - {{template: ball, position: [-0.02, 0, 0.01], velocity: [0, 0.2, 0],
         angular_velocity: [1, 1, 1]}}
      - {{template: grain, position: [0.005, -0.02, 0.03], orientation: [0.2, 0.9, -0.3, 0.1]}}
walls:
  - box: {{min: {list(BOX_MIN)}, max: {list(BOX_MAX)}, open_top: true, material: glass,
          motion: {{translation: {{velocity: {list(BOX_VELOCITY)}}}}}}}
effects:
  gravity: [0, 0, -9.81]
  contact: {{model: linear, stiffness: 2.0e3, damping: 0.05, tangential_damping: 0.5}}
  friction: true
  rotation: true
outputs:
  trajectories: {{every: {EVERY}, directory: frames}}
  vtk: {{every: {EVERY}, directory: paraview{{particles}}}}
"""

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def close(a, b, tolerance):
    return abs(a - b) <= tolerance


def run(talus, args):
    result = subprocess.run([talus] + args, capture_output=True, text=True)
    return result.returncode, result.stdout, result.stderr


def template_shapes(talus):
    """Body-frame vertices, face count and bounding radius of each polyhedron, from `talus shape`
    (the template the scene loader builds from the same spec)."""
    shapes = {}
    for name, spec in (("grain", GRAIN), ("block", CUBE)):
        code, out, err = run(talus, ["shape", spec])
        if code != 0:
            sys.exit(f"talus shape {spec} failed: {err}")
        shapes[name] = json.loads(out)
    return shapes


def expected_steps():
    total = round(END / TIME_STEP)
    return sorted(set(range(0, total + 1, EVERY)) | {total})


def read_pvd(path):
    root = ElementTree.parse(path).getroot()
    check(root.get("type") == "Collection", f"{path}: not a Collection")
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def read_vtp(path):
    reader = vtkXMLPolyDataReader()
    errors = []
    reader.AddObserver("ErrorEvent", lambda *_: errors.append(path))
    reader.SetFileName(path)
    reader.Update()
    check(not errors and reader.GetOutput() is not None, f"{path}: VTK could not read it")
    return reader.GetOutput()


def read_frame(path):
    """The trajectory CSV: rows by id, numbers as doubles (printed with 17 digits: exact)."""
    with open(path) as file:
        return {int(r["id"]): r for r in csv.DictReader(file)}


def vec(row, *keys):
    return [float(row[k]) for k in keys]


def rotation(w, x, y, z):
    """R(q) of a unit quaternion, body to world."""
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def cell_tuples(data, name):
    array = data.GetCellData().GetArray(name)
    if not check(array is not None, f"no cell array {name}"):
        return []
    return [array.GetTuple(i) for i in range(array.GetNumberOfTuples())]


def check_series(directory, name, steps):
    """The .pvd: one entry per output step, at time step * dt, naming a file that exists."""
    entries = read_pvd(os.path.join(directory, name))
    check(len(entries) == len(steps), f"{name}: {len(entries)} frames, expected {len(steps)}")
    for (time, file), step in zip(entries, steps):
        # The step adds dt each step: a rounding of 1e-16 relative per step, far below 1e-12.
        check(close(time, step * TIME_STEP, 1e-12 * max(step * TIME_STEP, TIME_STEP)),
              f"{name}: time {time} for step {step}")
        check(os.path.isfile(os.path.join(directory, file)), f"{name}: {file} missing")
    return entries


def check_surfaces(data, rows, shapes, label):
    """Counts, then per particle its cells' data and its points against the trajectory row."""
    templates = ["grain", "block", "ball"]
    counts = {"ball": (SPHERE_POINTS, SPHERE_FACES)}
    for name, shape in shapes.items():
        counts[name] = (shape["vertex_count"], shape["face_count"])
    points = sum(counts[templates[int(r["template"])]][0] for r in rows.values())
    cells = sum(counts[templates[int(r["template"])]][1] for r in rows.values())
    check(data.GetNumberOfPoints() == points, f"{label}: {data.GetNumberOfPoints()} points, "
          f"expected {points}")
    check(data.GetNumberOfPolys() == cells and data.GetNumberOfCells() == cells,
          f"{label}: {data.GetNumberOfCells()} cells, expected {cells} polygons")
    ids, templates_of, velocity, angular = (cell_tuples(data, n) for n in
                                            ("id", "template", "velocity", "angular_velocity"))
    particle_points = {}
    for c in range(data.GetNumberOfCells()):
        row = rows.get(int(ids[c][0]))
        if not check(row is not None, f"{label}: cell {c} of unknown id {ids[c][0]}"):
            continue
        # Cell data is the trajectory's doubles, bit for bit (binary in the .vtp, 17 digits in
        # the CSV).
        check(int(templates_of[c][0]) == int(row["template"]), f"{label}: cell {c} template")
        check(list(velocity[c]) == vec(row, "vx", "vy", "vz"), f"{label}: cell {c} velocity")
        check(list(angular[c]) == vec(row, "wx", "wy", "wz"), f"{label}: cell {c} angular")
        cell = data.GetCell(c)
        particle_points.setdefault(int(ids[c][0]), set()).update(
            cell.GetPointId(k) for k in range(cell.GetNumberOfPoints()))
    check(set(particle_points) == set(rows), f"{label}: particles drawn {sorted(particle_points)}")
    for pid, used in particle_points.items():
        check_posed_points(data, rows[pid], sorted(used), shapes, f"{label} particle {pid}")


def check_posed_points(data, row, used, shapes, label):
    position = vec(row, "x", "y", "z")
    template = ["grain", "block", "ball"][int(row["template"])]
    if template == "ball":
        check(len(used) == SPHERE_POINTS, f"{label}: {len(used)} sphere points")
        for p in used:  # on the sphere: the sines and cosines round to 1e-16 relative
            r = math.dist(data.GetPoint(p), position)
            check(close(r, BALL_RADIUS, 1e-12 * BALL_RADIUS), f"{label}: point {p} at {r}")
        return
    vertices = shapes[template]["vertices"]
    # The particle's points are its template's vertices in order (docs/scenes.md).
    check(used == list(range(used[0], used[0] + len(vertices))), f"{label}: points {used}")
    R = rotation(*vec(row, "qw", "qx", "qy", "qz"))
    for k, v in enumerate(vertices):
        expected = [position[i] + sum(R[i][j] * v[j] for j in range(3)) for i in range(3)]
        got = data.GetPoint(used[0] + k)
        # position + R v in double, here and in talus (another formula for R): some units of
        # 1e-16 of |position| + |v|; 1e-12 of it still catches a wrong vertex, sign or rotation.
        scale = math.hypot(*position) + math.hypot(*v)
        check(all(close(got[i], expected[i], 1e-12 * scale) for i in range(3)),
              f"{label}: vertex {k} at {got}, expected {expected}")


def check_points(data, rows, shapes, label):
    n = len(rows)
    check(data.GetNumberOfPoints() == n and data.GetNumberOfVerts() == n,
          f"{label}: {data.GetNumberOfPoints()} points, {data.GetNumberOfVerts()} vertices, "
          f"expected {n}")
    arrays = {name: data.GetPointData().GetArray(name) for name in
              ("id", "template", "orientation", "velocity", "angular_velocity", "bounding_radius")}
    complete = [check(array is not None and array.GetNumberOfTuples() == n,
                      f"{label}: point array {name}") for name, array in arrays.items()]
    if not all(complete):
        return
    check(arrays["orientation"].GetNumberOfComponents() == 4, f"{label}: orientation components")
    radii = [shapes["grain"]["bounding_radius"], shapes["block"]["bounding_radius"], BALL_RADIUS]
    for p in range(n):
        row = rows.get(int(arrays["id"].GetTuple1(p)))
        if not check(row is not None, f"{label}: point {p} of unknown id"):
            continue
        # Exact: the trajectory's doubles, as in check_surfaces.
        check(list(data.GetPoint(p)) == vec(row, "x", "y", "z"), f"{label}: point {p} position")
        check(list(arrays["orientation"].GetTuple(p)) == vec(row, "qw", "qx", "qy", "qz"),
              f"{label}: point {p} orientation")
        check(list(arrays["velocity"].GetTuple(p)) == vec(row, "vx", "vy", "vz"),
              f"{label}: point {p} velocity")
        check(list(arrays["angular_velocity"].GetTuple(p)) == vec(row, "wx", "wy", "wz"),
              f"{label}: point {p} angular velocity")
        template = int(arrays["template"].GetTuple1(p))
        check(template == int(row["template"]), f"{label}: point {p} template")
        check(arrays["bounding_radius"].GetTuple1(p) == radii[template], f"{label}: point {p} radius")


def check_walls(directory, steps):
    """An open box translating at BOX_VELOCITY: 10 triangles over its 8 corners, moved by v t."""
    entries = check_series(directory, "walls.pvd", steps)
    check(len({file for _, file in entries}) == len(entries), "walls: a moving wall's file per frame")
    for time, file in entries:
        data = read_vtp(os.path.join(directory, file))
        check(data.GetNumberOfPolys() == 10, f"{file}: {data.GetNumberOfPolys()} triangles")
        check(set(t[0] for t in cell_tuples(data, "wall")) == {0.0}, f"{file}: wall index")
        corners = sorted(tuple(c[i] + BOX_VELOCITY[i] * time for i in range(3))
                         for c in ((x, y, z) for x in (BOX_MIN[0], BOX_MAX[0])
                                   for y in (BOX_MIN[1], BOX_MAX[1])
                                   for z in (BOX_MIN[2], BOX_MAX[2])))
        got = sorted(data.GetPoint(p) for p in range(data.GetNumberOfPoints()))
        # v t added in double by talus and here: 1e-12 of the box's 0.1 m is far below a step's
        # motion of 2e-6 m, so a wall placed a step late fails.
        check(len(got) == 8 and all(close(g[i], c[i], 1e-13) for g, c in zip(got, corners)
                                    for i in range(3)), f"{file}: corners {got}")


def check_outputs(directory, points, shapes, label):
    """The files of a run of SCENE in `directory`: the series, each frame against the trajectory
    frame of its step, the walls."""
    pv, frames = os.path.join(directory, "paraview"), os.path.join(directory, "frames")
    steps = expected_steps()
    entries = check_series(pv, "particles.pvd", steps)
    for (time, file), step in zip(entries, steps):
        rows = read_frame(os.path.join(frames, f"trajectory_{step:09d}.csv"))
        data = read_vtp(os.path.join(pv, file))
        if points:
            check_points(data, rows, shapes, f"{label} {file}")
        else:  # surfaces: asked for, or the default for 4 particles
            check_surfaces(data, rows, shapes, f"{label} {file}")
    check_walls(pv, steps)


def check_run(talus, work, label, run_args, particles_key, shapes):
    directory = os.path.join(work, label)
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    scene = os.path.join(directory, "scene.yaml")
    with open(scene, "w") as file:
        file.write(SCENE.replace("{particles}", particles_key))
    code, out, err = run(talus, ["run", "--quiet", "--output", directory] + run_args + [scene])
    if code != 0:
        return code, err
    summary = json.loads(out)
    print(f"{label}: {summary['solver']} solver, backend {summary.get('backend', '-')}")
    check_outputs(directory, "points" in particles_key, shapes, label)
    return 0, ""


def main():
    talus, work = sys.argv[1], sys.argv[2]
    shapes = template_shapes(talus)
    runs = [("surfaces-default-cpu", ["--backend", "cpu"], ""),
            ("points-cpu", ["--backend", "cpu"], ", particles: points"),
            ("surfaces-auto", [], ", particles: surfaces"),
            ("points-auto", [], ", particles: points")]
    for label, args, key in runs:
        code, err = check_run(talus, work, label, args, key, shapes)
        check(code == 0, f"{label}: talus run failed ({code}): {err}")
    code, err = check_run(talus, work, "surfaces-reference", ["--solver", "reference"], "", shapes)
    if code != 0 and "built without the reference solver" in err:
        print("reference solver: not in this talus (no CGAL); its files are not checked")
    else:
        check(code == 0, f"reference: talus run failed ({code}): {err}")
    for failure in failures[:40]:
        print("FAILED:", failure)
    if failures:
        sys.exit(f"{len(failures)} checks failed")
    print("all checks passed")


if __name__ == "__main__":
    main()
