#!/usr/bin/python3
"""The scaling study of the method paper's §3.5 (Figs. 17-18) on talus's MPI ranks.

Writes the §3.5 packing (polyhedra placed at random in a domain 2 m tall whose x and y grow with
the particle count, a floor and four sides meshed at lambda = 1.8), settles it once (on one rank, or
--settle-ranks), then resumes it from the settled checkpoint on each rank count under `mpirun` and times the
measured steps: weak scaling (a fixed count per rank) and strong scaling (a fixed total).
README.md here gives every choice and its reason.

    /usr/bin/python3 experiments/scaling/run_scaling.py --talus build/talus \\
        [--ranks 1 2 4] [--per-rank 1000] [--total 4000] [--modes weak strong] \\
        [--settle-steps 7500] [--measure-steps 200] [--repeats 3] [--threads 1] \\
        [--settle-threads N] [--settle-ranks 1] [--output scratch/scaling] [--work DIR] \\
        [--keep-work] [--quick] \\
        [--mpirun mpirun] [--mpirun-args '--bind-to none'] [--backend cpu|cuda] \\
        [--commit SHA] [--diameter 0.05]

Writes into OUTPUT, each through a temporary file and a rename:
  scaling.json  the machine, the commit, the scene, the settles and one row per (mode, ranks):
                seconds per step, each stage's seconds per step (rank 0's), the exchange's
                seconds per step and its share of the step, speedup and efficiency (Eqs. 31-33),
                the exact commands, the backend (with --backend cuda, the machine's GPUs)
  scaling.png   Figs. 17-18 redrawn: speedup and efficiency against the rank count
  results.md    the table, with the machine, the commit, the backend, the launcher and the
                command

Exit status: 0 done; 1 a run failed; 2 a bad option (the message names it); 3 this machine cannot
run the study (no mpirun, or a talus built without MPI). Needs numpy and matplotlib (Debian's,
under /usr/bin/python3) for the figure.
"""

import argparse
import hashlib
import json
import math
import os
import platform
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

# ---------------------------------------------------------------------------------------------
# The scene (README.md, "The scene", says why each value is what it is)

HEIGHT = 2.0               # m: the domain's z extent, fixed (§3.5)
DIAMETER = 0.05            # m: the dodecahedron's circumscribed diameter (the default)
SPHERE_FRACTION = 0.25     # the particles' bounding spheres over the domain's volume at the start
LAMBDA = 1.8               # the wall mesh's resolution, L_c / L_m (the method paper's Eq. 29)
STEP_PER_DIAMETER = 1.6e-3  # s/m: dt = 1.6e-3 D, 0.19 of talus's critical step at any D
SEED = 35
MATERIAL = ("resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.8, "
            "restitution: 0.1}")

# The sizes. Full: 1000 particles a rank and a total of 4000 take 4 minutes on 2 idle cores
# (most of it the three settles); quick (CI): 5 s.
FULL = {"per_rank": 1000, "settle_steps": 7500, "measure_steps": 200, "repeats": 3}
QUICK = {"per_rank": 200, "settle_steps": 2500, "measure_steps": 50, "repeats": 1}

# What the paper states (§3.5; it gives no table): the efficiencies at 16 GPUs.
PAPER = {
    "strong": {"efficiency": 0.85, "ranks": 16,
               "statement": "strong-scaling efficiency above 85% up to 16 GPUs"},
    "weak": {"efficiency": 0.85, "ranks": 16, "per_gpu": 5.0e6,
             "statement": "weak-scaling efficiency with 5.0e6 particles per GPU dropping to "
                          "approximately 85% at 16 GPUs"},
}

EXIT_FAILED, EXIT_CANNOT, EXIT_UNFINISHED = 1, 3, 4  # and 2, argparse's, for a bad option
TALUS_STOPPED = 75  # talus run's exit status when --stop-after stopped it (with a checkpoint)


class CannotRun(Exception):
    """This machine cannot run the study (exit status 3)."""


class SettleUnfinished(Exception):
    """A settle stopped by --settle-sitting, its checkpoint written: call again to go on."""


class RunFailed(Exception):
    """A talus run failed or said something the study cannot use (exit status 1)."""


def box_side(count, diameter):
    """The domain's x = y extent, m, for `count` particles at the fixed initial spacing.

    The particles' bounding spheres fill SPHERE_FRACTION of the domain whatever the count, so the
    mean spacing (domain volume / count)^(1/3) = D (pi / (6 * 0.25))^(1/3) = 1.28 D stays the same
    and x y grows with the count at the fixed 2 m of z.
    """
    sphere = math.pi / 6 * diameter ** 3
    return math.sqrt(count * sphere / SPHERE_FRACTION / HEIGHT)


def smallest_count(diameter):
    """The fewest particles whose domain is 3 D wide: in a narrower column random placement runs
    out of room before 0.25 (60 particles, 1.8 D, placed 45)."""
    return math.ceil((3 * diameter) ** 2 * HEIGHT * SPHERE_FRACTION / (math.pi / 6 * diameter ** 3))


def time_step(diameter):
    return STEP_PER_DIAMETER * diameter


def cells(length, diameter):
    """Cells of the wall mesh along `length`: L_m = length / n closest to L_c / LAMBDA."""
    return max(1, round(length * LAMBDA / diameter))


def walls_text(side, diameter):
    """An open box (floor and four sides, 2 m tall) as an OBJ of square cells, two triangles
    each, every normal pointing inward (solver/scene/wall_meshes.hpp's convention). Vertices are
    shared, so each face is one planar patch (solver/walls/planar_patch_build.hpp). Returns the
    OBJ text, the triangle count and lambda along x (= y) and z."""
    nx, nz = cells(side, diameter), cells(HEIGHT, diameter)
    index = {}
    lines = []

    def vertex(i, j, k):  # grid indices along x, y, z
        key = (i, j, k)
        if key not in index:
            index[key] = len(index) + 1
            lines.append(f"v {side * i / nx!r} {side * j / nx!r} {HEIGHT * k / nz!r}")
        return index[key]

    faces = []

    def quad(a, b, c, d):  # normal (b - a) x (c - a)
        faces.append(f"f {a} {b} {c}")
        faces.append(f"f {a} {c} {d}")

    for i in range(nx):  # floor, normal +z
        for j in range(nx):
            quad(vertex(i, j, 0), vertex(i + 1, j, 0), vertex(i + 1, j + 1, 0), vertex(i, j + 1, 0))
    for j in range(nx):  # x = 0, normal +x
        for k in range(nz):
            quad(vertex(0, j, k), vertex(0, j + 1, k), vertex(0, j + 1, k + 1), vertex(0, j, k + 1))
    for j in range(nx):  # x = side, normal -x
        for k in range(nz):
            quad(vertex(nx, j, k), vertex(nx, j, k + 1), vertex(nx, j + 1, k + 1),
                 vertex(nx, j + 1, k))
    for i in range(nx):  # y = 0, normal +y
        for k in range(nz):
            quad(vertex(i, 0, k), vertex(i, 0, k + 1), vertex(i + 1, 0, k + 1),
                 vertex(i + 1, 0, k))
    for i in range(nx):  # y = side, normal -y
        for k in range(nz):
            quad(vertex(i, nx, k), vertex(i + 1, nx, k), vertex(i + 1, nx, k + 1),
                 vertex(i, nx, k + 1))
    text = ("# The scaling study's walls (experiments/scaling/run_scaling.py): an open box "
            f"{side!r} m square and {HEIGHT} m tall,\n# cells of {side / nx:.6g} x "
            f"{HEIGHT / nz:.6g} m, lambda = {diameter * nx / side:.4g} (x, y) and "
            f"{diameter * nz / HEIGHT:.4g} (z).\n" + "\n".join(lines + faces) + "\n")
    return text, len(faces), diameter * nx / side, diameter * nz / HEIGHT


def scene_text(count, diameter, settle_steps, measure_steps, walls_file):
    side = box_side(count, diameter)
    dt = time_step(diameter)
    end = (settle_steps + measure_steps) * dt
    low, high, top = repr(-diameter), repr(side + diameter), repr(HEIGHT + diameter)
    return f"""\
# The scaling study's packing (method paper section 3.5) for {count} particles, written by
# experiments/scaling/run_scaling.py: dodecahedra of {diameter} m placed at random, with random
# orientations, in a domain {HEIGHT} m tall and {side:.6g} m square (their bounding spheres fill
# {SPHERE_FRACTION} of it), falling under gravity into an open box meshed at lambda = {LAMBDA}.
# The settle runs steps 1 to {settle_steps} (checkpoint at {settle_steps}); each measured run
# resumes there and runs the {measure_steps} steps to time.end.
time: {{step: {dt!r}, end: {end!r}}}
seed: {SEED}
domain: {{min: [{low}, {low}, {low}], max: [{high}, {high}, {top}]}}

materials:
  {MATERIAL}

templates:
  grain: {{shape: dodecahedron:{diameter!r}, material: resin}}

particles:
  - random:
      template: grain
      region: {{box: {{min: [0, 0, 0], max: [{side!r}, {side!r}, {HEIGHT!r}]}}}}
      count: {count}
      random_orientation: true

walls:
  - mesh: {{name: bin, file: {walls_file}, material: resin}}

effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true

outputs:
  checkpoint: {{every: {settle_steps}, directory: checkpoints, keep: 1}}
  probes: {{every: {settle_steps}, file: probes.csv,
           quantities: [kinetic_energy, contact_count, bed_height]}}
"""


# ---------------------------------------------------------------------------------------------
# Small tools


def temporary_beside(path):
    """A new temporary file in `path`'s folder, with the permissions a plain open would give
    (mkstemp's are 0600)."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=os.path.basename(path) + ".", suffix=".tmp")
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, 0o666 & ~umask)
    return fd, tmp


def write_atomically(path, data):
    """Writes `data` (str or bytes) to `path` through a temporary file in its folder and a rename,
    so that a reader never sees half a file."""
    fd, tmp = temporary_beside(path)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def say(text):
    print(f"run_scaling: {text}", file=sys.stderr, flush=True)


def probe_row(path, step):
    """The probe row of `step` in a run's probes.csv (kinetic energy J, particle contacts, bed
    height m); None where there is none."""
    try:
        with open(path) as f:
            header = f.readline().strip().split(",")
            for line in f:
                values = line.strip().split(",")
                if len(values) == len(header) and int(values[1]) == step:
                    row = dict(zip(header, values))
                    return {"kinetic_energy_J": float(row["kinetic_energy"]),
                            "contacts": int(float(row["contact_count"])),
                            "bed_height_m": float(row["bed_height"])}
    except (OSError, ValueError, KeyError):
        pass
    return None


def binary_identity(path):
    """The binary's size and SHA-256: what tells a rebuilt talus. Its bytes, not its path or
    modification time: a binary unpacked again on the GPU machine at each call (the same bytes,
    a new mtime) must find the settle an earlier call wrote; a rebuilt one must not."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return f"{os.path.getsize(path)} sha256:{digest.hexdigest()}"


def machine():
    """The CPU model and its cores, from /proc/cpuinfo, and the cores this process may use."""
    model, logical, physical = None, 0, set()
    physical_id = core_id = None
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                key, value = key.strip(), value.strip()
                if key == "processor":
                    logical += 1
                elif key == "model name" and model is None:
                    model = value
                elif key == "physical id":
                    physical_id = value
                elif key == "core id":
                    core_id = value
                    physical.add((physical_id, core_id))
    except OSError:
        pass
    return {
        "cpu_model": model or platform.processor() or "unknown",
        "logical_cpus": logical or os.cpu_count(),
        "physical_cores": len(physical) or logical or os.cpu_count(),
        "usable_cpus": len(os.sched_getaffinity(0)),
        "hostname": platform.node(),
        "kernel": platform.release(),
    }


def gpus():
    """The GPUs as nvidia-smi lists them ("name, memory.total", one string a GPU) and how many
    lines it printed; ("unknown", 0) where nvidia-smi is missing or fails."""
    try:
        proc = subprocess.run(["nvidia-smi", "--query-gpu=name,memory.total",
                               "--format=csv,noheader"], capture_output=True, text=True,
                              timeout=60)
    except (OSError, subprocess.SubprocessError):
        return "unknown", 0
    lines = [line.strip() for line in proc.stdout.splitlines() if line.strip()]
    if proc.returncode != 0 or not lines:
        return "unknown", 0
    return lines, len(lines)


def backend_words(backend):
    return "CUDA backend" if backend == "cuda" else "host backend"


def git_commit(repo):
    try:
        out = subprocess.run(["git", "-C", repo, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, check=True)
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def mpi_environment(ranks, cores):
    """What Open MPI needs here: root's consent when run as root, and with more ranks than cores
    oversubscription and ranks that yield their core while they wait (tests/parallel/
    run_ranks.sh)."""
    env = {}
    if os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    if ranks > cores:
        env.update(OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
    return env


def command_text(env, argv):
    return " ".join([f"{k}={v}" for k, v in env.items()] + [shlex.quote(a) for a in argv])


def error_lines(text, count):
    """talus's own lines of a failed run's output (mpirun adds its banners after them), else its
    last `count` lines."""
    lines = text.strip().splitlines()
    own = [line for line in lines if line.startswith("talus")]
    return "\n".join((own or lines)[-count:])


def run_talus(argv, env_extra, what, may_stop=False, log=None):
    """Runs one talus command; returns (its summary JSON, its wall time in s). With `may_stop`,
    a run that --stop-after stopped (exit status 75) returns (None, its wall time). `log`: a file
    that gets the command and then talus's stderr as it is written (its setup's parts, progress
    and messages, e.g. TALUS_EXCHANGE_PROFILE's), so that a run killed from outside (a call's
    time running out) leaves what it said; without, stderr is kept for the error message."""
    env = dict(os.environ)
    env.update(env_extra)
    started = time.monotonic()
    try:
        if log:
            with open(log, "w") as f:
                f.write(command_text(env_extra, argv) + "\n")
                f.flush()
                proc = subprocess.run(argv, stdout=subprocess.PIPE, stderr=f, text=True, env=env)
            with open(log) as f:
                proc.stderr = f.read().split("\n", 1)[-1]
        else:
            proc = subprocess.run(argv, capture_output=True, text=True, env=env)
    except OSError as e:
        raise RunFailed(f"{what}: cannot start {argv[0]}: {e.strerror}")
    seconds = time.monotonic() - started
    if may_stop and proc.returncode == TALUS_STOPPED:
        return None, seconds
    if proc.returncode != 0:
        tail = error_lines(proc.stderr or proc.stdout, 15)
        raise RunFailed(f"{what} exited with status {proc.returncode}: "
                        f"{command_text(env_extra, argv)}\n{tail}")
    try:
        return json.loads(proc.stdout), seconds
    except json.JSONDecodeError:
        raise RunFailed(f"{what}: its output is not a talus summary (JSON): "
                        f"{proc.stdout[:300]!r}")


# ---------------------------------------------------------------------------------------------
# The runs


class Study:
    def __init__(self, args):
        self.args = args
        self.machine = machine()
        if args.backend == "cuda":  # each rank takes GPU (local rank mod GPUs); ranks may share
            self.machine["gpu_names"], self.machine["gpus"] = gpus()
        self.cores = self.machine["usable_cpus"]
        self.settles = {}       # count -> record
        self.measured = {}      # (ranks, count) -> record

    def check_mpi(self):
        """A talus built without MPI runs every process of `mpirun -np 2` alone (each writing the
        outputs); its summary then says one rank, or the second process is refused the output
        folder. A few steps of a small packing on 2 ranks tell (as tests/parallel/run_ranks.sh
        does)."""
        a = self.args
        folder = os.path.join(a.work, "mpi-check")
        os.makedirs(folder, exist_ok=True)
        obj = walls_text(box_side(200, a.diameter), a.diameter)[0]
        write_atomically(os.path.join(folder, "walls.obj"), obj)
        write_atomically(os.path.join(folder, "scene.yaml"),
                         scene_text(200, a.diameter, 2, 2, "walls.obj"))
        argv = a.mpirun + ["-np", "2"] + a.mpirun_args + [
            a.talus, "run", os.path.join(folder, "scene.yaml"), "--backend", a.backend,
            "--threads", "1", "--quiet", "--overwrite", "--output", os.path.join(folder, "out"),
            "--end", repr(2 * time_step(a.diameter))]
        env = dict(os.environ)
        env.update(mpi_environment(2, self.cores))
        try:
            proc = subprocess.run(argv, capture_output=True, text=True, env=env)
        except OSError as e:
            raise CannotRun(f"--mpirun: cannot start {a.mpirun[0]}: {e.strerror}")
        if '"ranks": 2' not in proc.stdout:
            tail = error_lines(proc.stderr or proc.stdout, 5)
            raise CannotRun(f"`{command_text(mpi_environment(2, self.cores), argv)}` did not run "
                            "on 2 ranks (no \"ranks\": 2 in its summary): talus was built "
                            "without MPI" + (" (with --backend cuda: or without CUDA, or no "
                                             "GPU is usable)" if a.backend == "cuda" else "") +
                            f", or mpirun failed (docs/parallel.md)\n{tail}")

    def settle(self, count):
        """Settles the packing of `count` particles on one rank for settle_steps steps (run to one
        step past, so that the checkpoint at settle_steps is written); returns its record."""
        if count in self.settles:
            return self.settles[count]
        a = self.args
        folder = os.path.join(a.work, f"packing-{count}")
        os.makedirs(folder, exist_ok=True)
        walls, scene = os.path.join(folder, "walls.obj"), os.path.join(folder, "scene.yaml")
        obj, triangles, lambda_xy, lambda_z = walls_text(box_side(count, a.diameter), a.diameter)
        yaml = scene_text(count, a.diameter, a.settle_steps, a.measure_steps, "walls.obj")
        run_dir = os.path.join(folder, "settled")
        done = os.path.join(folder, "settle.json")
        sittings_file = os.path.join(folder, "settle-sittings.json")
        checkpoint = os.path.join(run_dir, "checkpoints", f"checkpoint_{a.settle_steps:09d}.bin")
        binary = binary_identity(a.talus)
        # A count settled by an earlier call into the same --work, with the same scene, walls and
        # talus, is not settled again (the settled bytes would be the same).
        try:
            with open(done) as f:
                record = json.load(f)
            with open(scene) as f, open(walls) as g:
                same = f.read() == yaml and g.read() == obj
            if (same and record.get("talus_binary") == binary and os.path.isfile(checkpoint)
                    and record.get("backend", "cpu") == a.backend):
                record.update(reused=True, run_dir=run_dir)
                say(f"{count} particles: settled by an earlier call ({done}), not again")
                self.settles[count] = record
                return record
        except (OSError, ValueError):
            pass
        if os.path.exists(done):
            os.unlink(done)
        # A settle that --settle-sitting stopped in an earlier call (same scene, walls, talus and
        # backend) goes on from its checkpoint; the resumed run is the uninterrupted one to the
        # bit (docs/scenes.md, checkpoints), on any rank count.
        earlier = None
        try:
            with open(sittings_file) as f:
                earlier = json.load(f)
            with open(scene) as f, open(walls) as g:
                same = f.read() == yaml and g.read() == obj
            if not (same and earlier.get("talus_binary") == binary
                    and earlier.get("backend") == a.backend
                    and any(n.startswith("checkpoint_") and n.endswith(".bin")
                            for n in os.listdir(os.path.join(run_dir, "checkpoints")))):
                earlier = None
        except (OSError, ValueError):
            earlier = None
        end = (a.settle_steps + 1) * time_step(a.diameter)
        if earlier is None:
            if os.path.exists(sittings_file):
                os.unlink(sittings_file)
            write_atomically(walls, obj)
            write_atomically(scene, yaml)
            argv = [a.talus, "run", scene, "--backend", a.backend, "--threads",
                    str(a.settle_threads), "--output", run_dir, "--overwrite",
                    "--end", repr(end)]
        else:
            argv = [a.talus, "run", "--resume", os.path.join(run_dir, "checkpoints"),
                    "--backend", a.backend, "--threads", str(a.settle_threads),
                    "--end", repr(end)]
        if a.settle_sitting:
            argv += ["--stop-after", repr(a.settle_sitting)]
        # On several ranks (--settle-ranks) the settle gives the same bytes as on one: the
        # decomposed step's trajectories do not depend on the rank count (docs/parallel.md,
        # tests/parallel/run_ranks.sh), so it only saves time.
        env = {}
        if a.settle_ranks > 1:
            env = mpi_environment(a.settle_ranks, self.cores)
            argv = a.mpirun + ["-np", str(a.settle_ranks)] + a.mpirun_args + argv
        sittings = earlier["sittings"] if earlier else []
        say(("going on with" if earlier else "settling") + f" {count} particles: "
            f"{a.settle_steps} steps on "
            + (f"{a.settle_ranks} ranks" if a.settle_ranks > 1 else "one rank") + ", "
            f"{a.settle_threads} thread{'s' if a.settle_threads > 1 else ''}"
            + (", CUDA" if a.backend == "cuda" else "")
            + (f", sitting {len(sittings) + 1}" if a.settle_sitting or earlier else ""))
        # Not --quiet: its log (settle-<sitting>.log beside the scene) has the setup's parts as
        # they end and a progress line a second.
        summary, seconds = run_talus(argv, env, f"the settle of {count} particles",
                                     may_stop=True, log=os.path.join(
                                         folder, f"settle-{len(sittings) + 1}.log"))
        sittings.append({"command": command_text(env, argv), "process_seconds": seconds,
                         "finished": summary is not None})
        if summary is None:
            write_atomically(sittings_file, json.dumps(
                {"talus_binary": binary, "backend": a.backend, "sittings": sittings},
                indent=2) + "\n")
            raise SettleUnfinished(
                f"the settle of {count} particles stopped after --settle-sitting "
                f"{a.settle_sitting:g} s (sitting {len(sittings)}), its checkpoint in "
                f"{os.path.join(run_dir, 'checkpoints')}: run the same command again (the same "
                "--work) to go on")
        if summary.get("ranks", 1) != a.settle_ranks:
            raise RunFailed(f"the settle of {count} particles ran on {summary.get('ranks', 1)} "
                            f"rank(s); --settle-ranks asked for {a.settle_ranks}")
        # A resumed settle's summary counts the steps and the contacts from step 1 too (the
        # checkpoint carries the running sums).
        if summary.get("steps") != a.settle_steps + 1 or summary.get("particles") != count:
            raise RunFailed(f"the settle of {count} particles ran {summary.get('steps')} steps "
                            f"with {summary.get('particles')} particles; expected "
                            f"{a.settle_steps + 1} and {count}")
        if not os.path.isfile(checkpoint):
            raise RunFailed(f"the settle of {count} particles wrote no {checkpoint}")
        say(f"  {seconds:.1f} s; {summary.get('mean_contacts_per_step', 0):.0f} contacts a step "
            "on average")
        record = {
            "particles": count,
            "box_side_m": box_side(count, a.diameter),
            "wall_triangles": triangles,
            "lambda_xy": lambda_xy,
            "lambda_z": lambda_z,
            "steps": a.settle_steps,
            "threads": a.settle_threads,
            "ranks": a.settle_ranks,
            "backend": a.backend,
            "wall_seconds": summary["wall_seconds"],  # the last sitting's
            # talus's setup parts of the last sitting: the scene and walls read, the particles
            # made and checked, the step built, step 0 (or the checkpoint restored)
            "setup_seconds": summary.get("setup_seconds"),
            "process_seconds": sum(s["process_seconds"] for s in sittings),
            "sittings": len(sittings),
            "mean_contacts_per_step": summary.get("mean_contacts_per_step"),
            "at_settle_step": probe_row(os.path.join(run_dir, "probes.csv"), a.settle_steps),
            "command": sittings[0]["command"],
            "continued_by": [s["command"] for s in sittings[1:]],
            "talus_binary": binary,
            "reused": False,
        }
        write_atomically(done, json.dumps(record, indent=2) + "\n")
        if os.path.exists(sittings_file):
            os.unlink(sittings_file)
        record["run_dir"] = run_dir
        self.settles[count] = record
        return record

    def measure(self, ranks, count, repeat):
        """Resumes the settled packing of `count` particles on `ranks` ranks for measure_steps
        steps; returns the run's record."""
        a = self.args
        settled = self.settle(count)
        run_dir = os.path.join(a.work, f"packing-{count}", f"ranks-{ranks}-{repeat}")
        if os.path.exists(run_dir):
            shutil.rmtree(run_dir)
        # A copy of the settled run: the checkpoint's output root is relative to it, so the
        # resumed run writes into the copy and every rank count starts from the same bytes.
        shutil.copytree(settled["run_dir"], run_dir)
        env = mpi_environment(ranks, self.cores)
        argv = a.mpirun + ["-np", str(ranks)] + a.mpirun_args + [
            a.talus, "run", "--resume", os.path.join(run_dir, "checkpoints"), "--backend",
            a.backend, "--threads", str(a.threads), "--quiet"]
        say(f"measuring {count} particles on {ranks} rank{'s' if ranks > 1 else ''}: "
            f"{a.measure_steps} steps" + (f" (repeat {repeat + 1} of {a.repeats})"
                                          if a.repeats > 1 else ""))
        load = os.getloadavg()[0]
        summary, seconds = run_talus(argv, env, f"the run of {count} particles on {ranks} ranks",
                                     log=run_dir + ".stderr.log")
        if summary.get("ranks", 1) != ranks:
            raise CannotRun(f"talus ran {summary.get('ranks', 1)} rank(s) under "
                            f"`{' '.join(a.mpirun + ['-np', str(ranks)] + a.mpirun_args)}`: "
                            "it was built without MPI "
                            "(docs/parallel.md)")
        steps = summary["steps"] - summary.get("resumed_from_step", 0)
        if summary.get("resumed_from_step") != a.settle_steps or steps != a.measure_steps:
            raise RunFailed(f"the run of {count} particles on {ranks} ranks resumed at step "
                            f"{summary.get('resumed_from_step')} and ran {steps} steps; expected "
                            f"{a.settle_steps} and {a.measure_steps}")
        if summary.get("particles") != count:
            raise RunFailed(f"the run on {ranks} ranks ended with {summary.get('particles')} "
                            f"particles, not {count}")
        # The steps after the run's first (`steady` in talus's summary): the resumed run's setup
        # (reading the checkpoint, the walls' grid: about 20 s at a million particles) and its
        # first step (the first list, the boxes cut, the first ghosts) left out. A talus that
        # prints no `steady` is timed over the whole run, setup included.
        steady = summary.get("steady")
        timed = steady["steps"] if steady else steps
        source = steady if steady else summary
        wall = source["seconds"] if steady else summary["wall_seconds"]
        exchange = source.get("exchange_seconds", 0.0) if ranks > 1 else 0.0
        stages = {k: v / timed for k, v in source["stage_seconds"].items()}
        # Stages that ran on a stream of their own beside another (the CUDA step's wall stage
        # beside its pair stage: `stages_beside` in the summary, stage -> the stage it ran
        # beside): their seconds overlap that stage's, so the step's sum leaves them out.
        beside = summary.get("stages_beside", {})
        in_sum = sum(v for k, v in stages.items() if k not in beside)
        # The summary's mean is over the whole run (steps 1 to S + M, the checkpoint carries the
        # sum); the settle's over steps 1 to S + 1. Their difference is the sum over steps
        # S + 2 to S + M, the same contacts on any rank count (docs/parallel.md).
        total = summary["mean_contacts_per_step"] * summary["steps"]
        settle_total = settled["mean_contacts_per_step"] * (a.settle_steps + 1)
        contacts = (total - settle_total) / (steps - 1)
        record = {
            "ranks": ranks,
            "particles": count,
            "threads_per_rank": a.threads,
            "measured_steps": steps,
            "timed_steps": timed,  # the steps after the first (all of them from an older talus)
            "wall_seconds": summary["wall_seconds"],
            "timed_seconds": wall,
            "process_seconds": seconds,
            "seconds_per_step": wall / timed,
            "seconds_per_step_with_setup": summary["wall_seconds"] / steps,
            "stage_seconds_per_step": stages,
            "stages_beside": beside,
            "stages_seconds_per_step": in_sum,
            "exchange_seconds_per_step": exchange / timed,
            "exchange_share": exchange / wall,
            # Rank 0's time outside its stages and the exchange: the commands to the other ranks
            # and the agreement after each stage, where a rank waits for a slower one, and the
            # gaps between the stages' kernels (and, from a talus without `steady`, the setup;
            # with a stage beside another, the time it ran on after that one ended).
            "rest_seconds_per_step": wall / timed - in_sum - exchange / timed,
            "contacts_per_step": contacts,
            "pair_list_builds": summary.get("pair_list_builds"),
            "at_last_step": probe_row(os.path.join(run_dir, "probes.csv"),
                                      a.settle_steps + a.measure_steps),
            "oversubscribed": ranks * a.threads > self.cores,
            "load_average_before": load,
            "command": command_text(env, argv),
        }
        if ranks > 1 and "exchange_rebuild_seconds" in source:
            # Of the exchange: the rebuild vote (its wait for the slowest rank included) and the
            # rebuild steps (migration, the ghosts chosen again); the rest is the ghosts' updates.
            record["exchange_vote_seconds_per_step"] = source["exchange_vote_seconds"] / timed
            record["exchange_rebuild_seconds_per_step"] = (
                source["exchange_rebuild_seconds"] / timed)
        if "exchange_bytes" in summary:
            # Bytes sent to the other ranks, counted by the resumed run's step from its start as
            # exchange_seconds is (neither is carried by the checkpoint, and the settle ran on one
            # rank), so the run's own figure over its steps; 0 on one rank, as the exchange's
            # seconds. Left out where talus prints none.
            sent = source.get("exchange_bytes", summary["exchange_bytes"]) if ranks > 1 else 0.0
            record["exchange_bytes_per_step"] = sent / timed
        say(f"  {wall / timed * 1e3:.2f} ms a step, exchange {100 * exchange / wall:.1f} % "
            f"({seconds:.1f} s with start-up)")
        shutil.rmtree(run_dir)  # its numbers are in the record; the settled run stays
        return record

    def runs(self):
        """One row per (mode, ranks), with speedup and efficiency against the one-rank row.

        Each (ranks, count) that the modes ask for is run --repeats times, one pass over all of
        them after the other, so that a slow spell of the machine falls on every rank count
        alike; its row is the run with the median seconds per step (the lower of the two middle
        ones for an even count, so always a real run), the others' times listed beside it. A
        (ranks, count) that both modes ask for is run once and listed in both."""
        a = self.args
        wanted = []
        for mode in a.modes:
            for ranks in a.ranks:
                key = (ranks, a.per_rank * ranks if mode == "weak" else a.total)
                if key not in wanted:
                    wanted.append(key)
        if a.settle_only:
            for _, count in wanted:
                self.settle(count)
            return None
        samples = {key: [] for key in wanted}
        for repeat in range(a.repeats):
            for ranks, count in wanted:
                samples[(ranks, count)].append(self.measure(ranks, count, repeat))
        for key, runs in samples.items():
            ordered = sorted(runs, key=lambda r: r["seconds_per_step"])
            chosen = dict(ordered[(len(ordered) - 1) // 2])
            chosen["repeats"] = len(runs)
            chosen["samples_seconds_per_step"] = [r["seconds_per_step"] for r in runs]
            chosen["samples_load_average_before"] = [r["load_average_before"] for r in runs]
            self.measured[key] = chosen
        rows = []
        for mode in a.modes:
            base = None
            for ranks in a.ranks:
                count = a.per_rank * ranks if mode == "weak" else a.total
                row = dict(mode=mode, **self.measured[(ranks, count)])
                if ranks == 1:
                    base = row["seconds_per_step"]
                t_n = row["seconds_per_step"]
                if mode == "strong":
                    speedup = base / t_n                  # Eq. 31: s_s(N) = T_1 / T_N
                else:
                    speedup = ranks * base / t_n          # Eq. 33: s_w(N) = n T_1 / T_N, n = N
                row["speedup"] = speedup
                row["efficiency"] = speedup / ranks       # Eq. 32 (strong); s_w / N (weak)
                rows.append(row)
        return rows


# ---------------------------------------------------------------------------------------------
# The outputs


def figure(result, path):
    """Figs. 17-18 redrawn: speedup and efficiency against the rank count, strong (top) and
    weak (bottom), with the ideal line and the paper's statements at 16 GPUs."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cores = result["machine"]["usable_cpus"]
    fig, axes = plt.subplots(2, 2, figsize=(10, 8.2))
    ranks_all = sorted({r["ranks"] for r in result["runs"]})
    top = max(16, max(ranks_all))
    ticks = [n for n in (1, 2, 4, 8, 16, 32, 64) if n <= top]
    for row, mode, fig_name in ((0, "strong", "Fig. 17"), (1, "weak", "Fig. 18")):
        runs = [r for r in result["runs"] if r["mode"] == mode]
        ax_s, ax_e = axes[row]
        if not runs:
            for ax in (ax_s, ax_e):
                ax.text(0.5, 0.5, f"no {mode} runs", ha="center", transform=ax.transAxes)
            continue
        n = [r["ranks"] for r in runs]
        label = (f"talus, {runs[0]['particles']} particles" if mode == "strong"
                 else f"talus, {runs[0]['particles']} particles a rank")
        ax_s.plot([1, top], [1, top], color="0.5", ls="--", label="ideal")
        ax_s.plot(n, [r["speedup"] for r in runs], "o-", color="C0", label=label + " (median)")
        ax_s.set_ylabel("speedup " + ("$s_s = T_1/T_N$ (Eq. 31)" if mode == "strong"
                                      else "$s_w = N\\,T_1/T_N$ (Eq. 33)"))
        ax_e.axhline(1.0, color="0.5", ls="--", label="ideal")
        ax_e.plot(n, [r["efficiency"] for r in runs], "o-", color="C0", label=label + " (median)")
        if max(r["repeats"] for r in runs) > 1:
            # Each repeat's time against the median one-rank time: the machine's spread.
            base = runs[0]["seconds_per_step"]  # T_1: --ranks holds 1, sorted first
            for ax, per_rank in ((ax_s, False), (ax_e, True)):
                xs, ys = [], []
                for r in runs:
                    for t in r["samples_seconds_per_step"]:
                        speedup = (r["ranks"] if mode == "weak" else 1) * base / t
                        xs.append(r["ranks"])
                        ys.append(speedup / r["ranks"] if per_rank else speedup)
                ax.plot(xs, ys, ".", color="C0", alpha=0.45, label="each repeat")
        paper = result["paper"][mode]
        if mode == "strong":
            ax_e.plot([1, paper["ranks"]], [paper["efficiency"]] * 2, color="C3", ls=":",
                      label="paper: above 85 % up to 16 GPUs\n(statement; no table)")
        else:
            ax_e.plot([paper["ranks"]], [paper["efficiency"]], "s", color="C3",
                      label="paper: about 85 % at 16 GPUs,\n5.0e6 a GPU (statement; no table)")
        ax_e.set_ylabel("efficiency " + ("$s_s/N$ (Eq. 32)" if mode == "strong"
                                         else "$s_w/N$"))
        low = min([0.0] + [r["efficiency"] for r in runs])
        ax_e.set_ylim(min(0, low - 0.05), max(1.15, max(r["efficiency"] for r in runs) + 0.1))
        for ax, what in ((ax_s, "speedup"), (ax_e, "efficiency")):
            ax.set_xscale("log", base=2)
            ax.set_xticks(ticks)
            ax.set_xticklabels([str(t) for t in ticks])
            ax.set_xlim(0.8, top * 1.25)
            if cores < top:
                ax.axvspan(cores * 2 ** 0.5, top * 1.25, color="0.92", zorder=0,
                           label=f"ranks > {cores} cores: oversubscribed")
            ax.set_xlabel("ranks N (the paper: GPUs)")
            ax.set_title(f"{fig_name} ({mode} scaling): {what}", fontsize=10)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7.5, loc="upper left" if what == "speedup" else "center right")
        low = min([0.5] + [r["speedup"] for r in runs])
        yticks = [t for t in (0.125, 0.25, 0.5) if t >= low / 2] + ticks
        ax_s.set_yscale("log", base=2)
        ax_s.set_yticks(yticks)
        ax_s.set_yticklabels([f"{t:g}" for t in yticks])
        ax_s.set_ylim(min(yticks) * 0.8, top * 1.25)
    m = result["machine"]
    if result["backend"] == "cuda":
        on = f"CUDA backend, {m['gpus']} GPU{'s' if m['gpus'] != 1 else ''}"
    else:
        on = f"host backend, {result['threads_per_rank']} thread a rank"
    fig.suptitle(f"talus on MPI ranks ({on}): {m['cpu_model']}, {m['usable_cpus']} cores; "
                 f"commit {result['commit']}", fontsize=10)
    fig.tight_layout()
    fd, tmp = temporary_beside(path)
    os.close(fd)
    try:
        fig.savefig(tmp, format="png", dpi=110)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
        plt.close(fig)


def stages_in_sum(run):
    """A row's stages a step as the step's sum: less the stages that ran beside another (a row
    from a driver before `stages_seconds_per_step`: all of them)."""
    if "stages_seconds_per_step" in run:
        return run["stages_seconds_per_step"]
    return sum(run["stage_seconds_per_step"].values())


def beside_words(result):
    """Which stages ran beside another in the rows, in words: 'none here', or e.g.
    '`wall_contacts` beside `pair_contacts` in every row'."""
    pairs = sorted({(k, v) for r in result["runs"] for k, v in r.get("stages_beside", {}).items()})
    if not pairs:
        return "none here"
    every = all(r.get("stages_beside") for r in result["runs"])
    return (", ".join(f"`{k}` beside `{v}`" for k, v in pairs)
            + (" in every row" if every else " in the rows whose talus said so"))


def settle_ranks_words(settles):
    """'one rank', '4 ranks' or '1 and 4 ranks': the ranks the settles ran on."""
    counts = sorted({s.get("ranks", 1) for s in settles}) or [1]
    if counts == [1]:
        return "one rank"
    return " and ".join(str(c) for c in counts) + " ranks"


def markdown(result):
    m = result["machine"]
    gpu_words = ""
    if result["backend"] == "cuda":
        names = m["gpu_names"]
        gpu_words = (f", {m['gpus']} GPU{'s' if m['gpus'] != 1 else ''} ({'; '.join(names)})"
                     if names != "unknown" else ", GPUs unknown (nvidia-smi failed)")
    launcher = " ".join([result["mpirun"][0] if result["mpirun"] else "mpirun", "-np", "N"]
                        + result["mpirun_args"])
    lines = [
        "# Scaling study: results",
        "",
        f"Machine: {m['cpu_model']}, {m['physical_cores']} cores ({m['logical_cpus']} logical, "
        f"{m['usable_cpus']} usable)" + gpu_words + f"; talus commit `{result['commit']}`, "
        f"{backend_words(result['backend'])} (`--backend {result['backend']}`), "
        f"{result['threads_per_rank']} thread a rank; launcher `{launcher}`. Command (from the "
        f"repository root, {result['driver_wall_seconds']:.0f} s in all):",
        "",
        "    " + result["driver_command"],
        "",
        f"The packing: dodecahedra of {result['scene']['diameter_m']} m settled "
        f"{result['scene']['settle_steps']} steps ({result['scene']['settle_seconds']:.3g} s) on "
        f"{settle_ranks_words(result['settles'])} (the same bytes on any count), then "
        f"{result['scene']['measure_steps']} steps measured on each rank count "
        "(experiments/scaling/README.md). s/step: the resumed run's wall-clock seconds after its "
        "first step (its summary's `steady`: the setup and the first step left out) over those "
        "steps; stages: the sum of rank 0's `stage_seconds` over the same steps (less a stage "
        "that ran beside another, whose seconds overlap that one's: " + beside_words(result) +
        "); the exchange is "
        "the most any rank spent exchanging, waiting included; rest: s/step less the two (rank "
        "0's commands to the other ranks, the waits after each stage, the gaps between kernels); "
        "each (ranks, "
        "particles) was run as many times as the last columns list, one pass over all of them "
        "after the other, and the row is the run with the median s/step; load before: the "
        "machine's 1-minute load average as each run started.",
        "",
        "| mode | ranks | particles | s/step | stages s/step | exchange s/step | exchange share | "
        "rest s/step | contacts/step | speedup | efficiency | s/step of each repeat | "
        "load before |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result["runs"]:
        lines.append(
            f"| {r['mode']} | {r['ranks']}{' (oversubscribed)' if r['oversubscribed'] else ''} "
            f"| {r['particles']} | {r['seconds_per_step']:.4g} | "
            f"{stages_in_sum(r):.4g} | "
            f"{r['exchange_seconds_per_step']:.3g} | {100 * r['exchange_share']:.1f} % | "
            f"{r['rest_seconds_per_step']:.3g} | {r['contacts_per_step']:.0f} | "
            f"{r['speedup']:.3f} | {100 * r['efficiency']:.1f} % | "
            f"{', '.join(f'{t:.4g}' for t in r['samples_seconds_per_step'])} | "
            f"{', '.join(f'{x:.2f}' for x in r['samples_load_average_before'])} |")
    lines += ["", f"Settles ({settle_ranks_words(result['settles'])}, "
              f"{result['settles'][0]['threads']} threads; the state at "
              "the settled step from the probes):", "",
              "| particles | box side, m | wall triangles | lambda (x, y / z) | s | contacts | "
              "kinetic energy, J | bed height, m |",
              "|---|---|---|---|---|---|---|---|"]
    for s in result["settles"]:
        at = s["at_settle_step"] or {"contacts": float("nan"), "kinetic_energy_J": float("nan"),
                                     "bed_height_m": float("nan")}
        lines.append(f"| {s['particles']} | {s['box_side_m']:.4f} | {s['wall_triangles']} | "
                     f"{s['lambda_xy']:.3f} / {s['lambda_z']:.3f} | {s['wall_seconds']:.1f} | "
                     f"{at['contacts']} | {at['kinetic_energy_J']:.3g} | "
                     f"{at['bed_height_m']:.3f} |")
    if any(r["oversubscribed"] for r in result["runs"]):
        lines += ["", f"This machine has {m['usable_cpus']} cores: the runs marked oversubscribed "
                  "share them among more ranks than cores, so their times show the exchange's "
                  "correctness and cost, not scaling."]
    if (result["backend"] == "cuda" and m["gpus"] > 0
            and any(r["ranks"] > m["gpus"] for r in result["runs"])):
        lines += ["", f"{m['gpus']} GPU{'s' if m['gpus'] != 1 else ''} here: where there are more "
                  "ranks than GPUs, several ranks share one (each takes GPU local rank mod the "
                  "GPU count), so those rows measure the decomposition's cost, not scaling."]
    lines += ["", "The paper (§3.5) states, without a table: " + result["paper"]["strong"]
              ["statement"] + "; " + result["paper"]["weak"]["statement"] + ".",
              "", "What the committed runs say: experiments/scaling/README.md, \"Results\".", ""]
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Options


def positive_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def positive_float(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def parse_arguments(argv):
    p = argparse.ArgumentParser(
        description="The scaling study of the method paper's section 3.5 (Figs. 17-18) on "
                    "talus's MPI ranks (experiments/scaling/README.md).")
    p.add_argument("--talus", default=os.path.join(REPO, "build", "talus"),
                   help="the talus binary (default: build/talus of this repository)")
    p.add_argument("--ranks", type=positive_int, nargs="+", default=None, metavar="N",
                   help="the rank counts, 1 among them (default: 1 2 4)")
    p.add_argument("--per-rank", type=positive_int, default=None, metavar="COUNT",
                   help="weak scaling: particles a rank (default 1000; --quick 200)")
    p.add_argument("--total", type=positive_int, default=None, metavar="COUNT",
                   help="strong scaling: the total (default: --per-rank times the largest "
                        "rank count, so that it shares the weak study's settle)")
    p.add_argument("--modes", nargs="+", choices=("weak", "strong"), default=["weak", "strong"],
                   help="which studies (default: both)")
    p.add_argument("--settle-steps", type=positive_int, default=None, metavar="STEPS",
                   help="steps settled on one rank before measuring (default 7500, 0.6 s: "
                        "the bed at rest; --quick 2500)")
    p.add_argument("--measure-steps", type=positive_int, default=None, metavar="STEPS",
                   help="steps measured on each rank count (default 200; --quick 50); at "
                        "least 2 and at most --settle-steps")
    p.add_argument("--repeats", type=positive_int, default=None, metavar="R",
                   help="runs of each rank count, the median kept (default 3; --quick 1)")
    p.add_argument("--threads", type=positive_int, default=1, metavar="N",
                   help="each rank's --threads (default 1)")
    p.add_argument("--settle-threads", type=positive_int, default=None, metavar="N",
                   help="threads of each rank of the settle (default: the usable cores shared "
                        "among the --settle-ranks; --quick 1)")
    p.add_argument("--settle-ranks", type=positive_int, default=1, metavar="K",
                   help="ranks of the settle, under --mpirun (default 1; the settled bytes are "
                        "the same on any count, so K > 1 only saves time)")
    p.add_argument("--settle-sitting", type=positive_float, default=None, metavar="S",
                   help="stop each settle after S seconds (talus run --stop-after) with a "
                        "checkpoint and exit with status 4; the same command again goes on from "
                        "it: settles longer than a sitting (default: none)")
    p.add_argument("--settle-only", action="store_true",
                   help="settle the counts the study needs and stop (needs --work): settles "
                        "on a busy machine, the measured runs later on a quiet one")
    p.add_argument("--diameter", type=positive_float, default=DIAMETER, metavar="M",
                   help=f"the dodecahedra's circumscribed diameter, m (default {DIAMETER}); "
                        "the time step and the wall cells follow it")
    p.add_argument("--output", default="scratch/scaling", metavar="DIR",
                   help="where scaling.json, scaling.png and results.md go "
                        "(default scratch/scaling)")
    p.add_argument("--work", default=None, metavar="DIR",
                   help="scenes, settled checkpoints and runs (default: a temporary folder, "
                        "removed at the end); a count that an earlier call settled there with "
                        "the same scene, walls and talus is not settled again")
    p.add_argument("--keep-work", action="store_true",
                   help="keep the temporary work folder")
    p.add_argument("--quick", action="store_true",
                   help="CI's size: 200 particles a rank, 2500 steps settled, 50 measured")
    p.add_argument("--mpirun", default="mpirun", metavar="CMD",
                   help="the launcher and its options, split as a shell would (default mpirun); "
                        "-np N is added")
    p.add_argument("--mpirun-args", default="", metavar="ARGS",
                   help="options after `mpirun -np N`, split as a shell would (default none), "
                        "e.g. '--bind-to none'")
    p.add_argument("--backend", choices=("cpu", "cuda"), default="cpu",
                   help="talus run's --backend for the settle and every measured run (default "
                        "cpu); cuda: each rank takes the GPU of its local rank mod the GPU count")
    p.add_argument("--commit", default=None, metavar="SHA",
                   help="the talus commit to record (default: git rev-parse --short HEAD of "
                        "this repository)")
    a = p.parse_args(argv)

    size = QUICK if a.quick else FULL
    for key in ("per_rank", "settle_steps", "measure_steps", "repeats"):
        if getattr(a, key) is None:
            setattr(a, key, size[key])
    a.modes = list(dict.fromkeys(a.modes))  # each once, in the order given
    if a.ranks is None:
        a.ranks = [1, 2, 4]
    if len(set(a.ranks)) != len(a.ranks):
        p.error(f"--ranks: a rank count given twice: {' '.join(map(str, a.ranks))}")
    if 1 not in a.ranks:
        p.error("--ranks: 1 must be among the rank counts: Eqs. 31-33 divide by the one-rank "
                "time T_1")
    a.ranks.sort()
    if a.total is None:
        a.total = a.per_rank * max(a.ranks)
    if a.measure_steps < 2:
        p.error(f"--measure-steps: expected at least 2 steps, got {a.measure_steps} (the "
                "contacts of the measured steps are counted from the second one)")
    if a.measure_steps > a.settle_steps:
        p.error(f"--measure-steps: {a.measure_steps} is more than --settle-steps "
                f"({a.settle_steps}): the scene checkpoints every --settle-steps steps, and a "
                "checkpoint would fall within the measured steps")
    for option, count in (("--per-rank", a.per_rank), ("--total", a.total)):
        if count > 2 ** 31 - 1:
            p.error(f"{option}: {count} particles is above talus's limit of 2^31 - 1")
        if count < smallest_count(a.diameter):
            p.error(f"{option}: {count} particles make a domain "
                    f"{box_side(count, a.diameter) / a.diameter:.2g} diameters wide, where random "
                    f"placement runs out of room; ask for at least {smallest_count(a.diameter)} "
                    "(3 diameters)")
    if a.settle_only and a.work is None:
        p.error("--settle-only: give --work too: the measuring call reuses the settles there")
    if a.settle_sitting is not None and a.work is None:
        p.error("--settle-sitting: give --work too: the next call goes on from the stopped "
                "settle's checkpoint there")
    if a.settle_threads is None:  # quick: one, which a busy machine slows the least
        # Each rank its share of the cores: K ranks of all the cores each would start K threads
        # a core (the random fill's batches wait at a barrier for every thread).
        a.settle_threads = 1 if a.quick else max(1, len(os.sched_getaffinity(0)) // a.settle_ranks)
    talus = shutil.which(a.talus) if os.sep not in a.talus else a.talus
    if not talus or not os.path.isfile(talus):
        p.error(f"--talus: no such file: {a.talus}")
    if not os.access(talus, os.X_OK):
        p.error(f"--talus: not executable: {a.talus}")
    a.talus = os.path.abspath(talus)
    try:
        a.mpirun = shlex.split(a.mpirun)
    except ValueError as e:
        p.error(f"--mpirun: cannot split {a.mpirun!r}: {e}")
    if not a.mpirun:
        p.error("--mpirun: empty")
    try:
        a.mpirun_args = shlex.split(a.mpirun_args)
    except ValueError as e:
        p.error(f"--mpirun-args: cannot split {a.mpirun_args!r}: {e}")
    if a.work is not None and os.path.exists(a.work) and not os.path.isdir(a.work):
        p.error(f"--work: not a folder: {a.work}")
    if os.path.exists(a.output) and not os.path.isdir(a.output):
        p.error(f"--output: not a folder: {a.output}")
    return a


def main(argv):
    a = parse_arguments(argv)
    if shutil.which(a.mpirun[0]) is None:
        say(f"--mpirun: '{a.mpirun[0]}' is not found (scripts/setup installs Open MPI)")
        return EXIT_CANNOT
    started = time.monotonic()
    temporary = a.work is None
    a.work = os.path.abspath(a.work or tempfile.mkdtemp(prefix="talus-scaling-"))
    os.makedirs(a.work, exist_ok=True)
    study = Study(a)
    try:
        if max(a.ranks) > 1:
            study.check_mpi()
        rows = study.runs()
        if rows is None:
            say("settled (--settle-only): "
                + ", ".join(f"{c} particles" for c in sorted(study.settles)) + f" in {a.work}")
            return 0
    except CannotRun as e:
        say(str(e))
        return EXIT_CANNOT
    except SettleUnfinished as e:
        say(str(e))
        return EXIT_UNFINISHED
    except RunFailed as e:
        say(str(e))
        return EXIT_FAILED
    finally:
        if temporary and not a.keep_work:
            shutil.rmtree(a.work, ignore_errors=True)
        elif temporary:
            say(f"work folder kept: {a.work}")
    dt = time_step(a.diameter)
    settles = [{k: v for k, v in s.items() if k != "run_dir"}
               for _, s in sorted(study.settles.items())]
    try:
        mpi_version = subprocess.run(a.mpirun[:1] + ["--version"], capture_output=True,
                                     text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        mpi_version = "unknown"
    result = {
        "study": "method paper section 3.5, Figs. 17-18: strong and weak scaling over talus's "
                 f"MPI ranks ({backend_words(a.backend)}); experiments/scaling/README.md",
        "machine": study.machine,
        "commit": a.commit or git_commit(REPO),
        "talus": a.talus,
        "mpi": mpi_version,
        "backend": a.backend,
        "mpirun": a.mpirun,
        "mpirun_args": a.mpirun_args,
        "threads_per_rank": a.threads,
        "driver_command": "/usr/bin/python3 " + " ".join(
            shlex.quote(x) for x in [os.path.relpath(os.path.abspath(__file__), REPO)] + argv),
        "driver_wall_seconds": time.monotonic() - started,
        "scene": {
            "template": f"dodecahedron:{a.diameter!r}",
            "diameter_m": a.diameter,
            "height_m": HEIGHT,
            "bounding_sphere_fraction": SPHERE_FRACTION,
            "mean_spacing_m": a.diameter * (math.pi / 6 / SPHERE_FRACTION) ** (1 / 3),
            "lambda_target": LAMBDA,
            "material": MATERIAL,
            "contact": "volume, friction, rotation",
            "gravity": [0, 0, -9.81],
            "time_step_s": dt,
            "settle_steps": a.settle_steps,
            "settle_seconds": a.settle_steps * dt,
            "measure_steps": a.measure_steps,
            "seed": SEED,
        },
        "per_rank": a.per_rank,
        "total": a.total,
        "settles": settles,
        "runs": rows,
        "paper": PAPER,
        "equations": {
            "31": "s_s(N) = T_1 / T_N (strong: the same total on 1 and N ranks)",
            "32": "eta(N) = s_s(N) / N",
            "33": "s_w(N) = n T_1 / T_N, n = N (weak: the same count a rank); efficiency "
                  "s_w(N) / N",
            "T": "seconds per measured step: the resumed run's wall_seconds over its steps",
        },
    }
    os.makedirs(a.output, exist_ok=True)
    write_atomically(os.path.join(a.output, "scaling.json"), json.dumps(result, indent=2) + "\n")
    figure(result, os.path.join(a.output, "scaling.png"))
    write_atomically(os.path.join(a.output, "results.md"), markdown(result))
    say(f"wrote {os.path.join(a.output, 'scaling.json')}, scaling.png and results.md "
        f"({result['driver_wall_seconds']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
