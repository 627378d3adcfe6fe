#!/usr/bin/python3
"""ctest `fixed_bed_quick`: the fixed-bed driver end to end at CI's size (fixed_bed.py --quick:
60 pellets in a 0.12 m piece of the §4.2 tube, on the host), its bed.json checked.

    test_quick.py TALUS WORK_DIR

The run is stopped after 5 s (--time-limit: SIGTERM, a checkpoint) and continued (--continue),
both with --prune-frames. Checks, each a number that a broken driver, scene or analysis gets
wrong:
  - the run ended in two sittings; after each, one frame left, and filling.json holds the first
    sitting's frames; the filling in bed.json has a line for every frame the run wrote, from
    step 0 to its last at one interval (none lost to the pruning);
  - every pellet fed is in the tube at the end (none lost through the wall or the floor);
  - the random points find the pellets' summed volume within 1 % + 4 sampling errors (the
    contacts' overlaps are well below 1 % of a pellet's volume at this stiffness; a wrong
    quaternion convention or face plane misses tens of percent);
  - the bed's porosity lies in [0.30, 0.60]: cylinders of aspect 1 poured into a tube 4.5 pellet
    diameters wide pack at 0.35 to 0.50 in experiments and simulations, a thin bed of 60 a little
    looser; a bed that did not form or pellets overlapping deeply fall outside;
  - the ring at the wall is the most porous of the profile (a wall admits no pellet's interior
    beyond its contact points: > 0.7), the mean |cos| of the axes lies in (0, 1);
  - bed.md and bed.png are written; stiffness_study.py --collect, given this run as its case at
    1e6 Pa, tabulates it alone with this bed's porosity.
Skipped (77) without /usr/bin/python3's numpy and matplotlib.
"""
import importlib.util
import json
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
    shutil.rmtree(work, ignore_errors=True)
    driver = [sys.executable, os.path.join(HERE, "fixed_bed.py"), "--talus", talus,
              "--threads", "2", "--points", "60000"]
    # Stopped after 5 s (the run takes 30 s or more here), then continued: the path a GPU run
    # longer than one sitting takes.
    # --prune-frames: each sitting's frames digested into filling.json, all but the newest
    # removed (a GPU run carried between machines).
    proc = subprocess.run(driver + ["--quick", "--backend", "cpu", "--output", work,
                                    "--time-limit", "5", "--prune-frames"],
                          capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 3:
        print(f"fixed_bed.py --time-limit 5 exited with {proc.returncode}, expected 3 (stopped)")
        return 1
    frames = os.listdir(os.path.join(work, "run", "frames"))
    frames = [f for f in frames if f.startswith("trajectory_")]
    digested = json.load(open(os.path.join(work, "filling.json")))
    if len(frames) != 1 or len(digested) < 2:
        print(f"after the pruned first sitting: {len(frames)} frames (expected 1), "
              f"{len(digested)} lines in filling.json (expected the sitting's frames, > 1)")
        return 1
    proc = subprocess.run(driver + ["--continue", work, "--prune-frames"], capture_output=True,
                          text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 0:
        print(f"fixed_bed.py --continue exited with {proc.returncode}")
        return 1
    bed = json.load(open(os.path.join(work, "bed.json")))
    r = bed["result"]
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    check(bed.get("finished") and bed.get("sittings") == 2, f"run.json: finished "
          f"{bed.get('finished')}, sittings {bed.get('sittings')}; expected true and 2")
    check(r["pellets"] == bed["pellets_fed"] == 60, f"{r['pellets']} pellets in the tube, fed "
          f"{bed['pellets_fed']}, expected 60")
    v = r["volume_check"]
    check(v is not None and abs(v["found_over_summed"] - 1) <= 0.01 + 4 * v["error"],
          f"the sampled solid volume over the pellets' summed volume: {v}")
    check("porosity" in r and 0.30 <= r["porosity"] <= 0.60,
          f"porosity {r.get('porosity')} outside [0.30, 0.60]")
    profile = r.get("radial_profile", [])
    check(len(profile) > 1 and profile[-1]["porosity"] > 0.7 and
          profile[-1]["porosity"] == max(p["porosity"] for p in profile),
          "the ring at the wall is not the most porous (> 0.7): "
          + str([round(p["porosity"], 3) for p in profile]))
    check(0 < r.get("orientation", {}).get("mean_abs_cos", -1) < 1, "no orientations")
    # The slabs along the bed split the core's points: their point-weighted porosity is the
    # core's (to rounding, 1e-9), and every point lies in one.
    axial = r.get("axial_profile", [])
    n = sum(p["points"] for p in axial)
    check(n == r["points"] and abs(sum(p["porosity"] * p["points"] for p in axial) / n
                                   - r["porosity"]) < 1e-9,
          f"the axial slabs: {n} points of {r['points']}, {axial}")
    # The height curve over both pruned sittings: a line for every frame the run wrote, from
    # step 0 to its last, at one interval (a sitting's frames lost to the pruning leave a gap).
    steps = [f["step"] for f in bed["filling"]]
    gaps = {b - a for a, b in zip(steps, steps[1:])}
    check(len(steps) > 2 and steps[0] == 0 and len(gaps) == 1 and steps[-1] == bed["steps"],
          f"the filling's frames: steps {steps[:3]} ... {steps[-2:]} (intervals {sorted(gaps)}), "
          f"the run's last step {bed.get('steps')}")
    left = [f for f in os.listdir(os.path.join(work, "run", "frames"))
            if f.startswith("trajectory_")]
    check(len(left) == 1, f"{len(left)} frames left after the pruned run; expected 1")
    for name in ("bed.md", "bed.png"):
        path = os.path.join(work, name)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"{name}: not written")
    # stiffness_study.py --collect over this run, placed as its case E1e6-s1: one case, whose
    # porosity is this bed's, and the table and figure written.
    study_dir = os.path.abspath(work).rstrip("/") + "-study"
    shutil.rmtree(study_dir, ignore_errors=True)
    os.makedirs(study_dir)
    os.symlink(os.path.abspath(work), os.path.join(study_dir, "E1e6-s1"))
    proc = subprocess.run([sys.executable, os.path.join(HERE, "stiffness_study.py"), "--collect",
                           "--output", study_dir, "--moduli", "1e6", "1e7", "--seeds", "1"],
                          capture_output=True, text=True)
    check(proc.returncode == 0, f"stiffness_study.py --collect: {proc.stderr[-2000:]}")
    if proc.returncode == 0:
        study = json.load(open(os.path.join(study_dir, "stiffness.json")))
        got = [(c["youngs_modulus_pa"], c["porosity"]) for c in study["cases"]]
        check(got == [(1e6, r["porosity"])] and bed["youngs_modulus_pa"] == 1e6,
              f"stiffness_study.py collected {got}; expected this bed's "
              f"({bed.get('youngs_modulus_pa')}, {r['porosity']})")
        for name in ("stiffness.md", "stiffness.png"):
            path = os.path.join(study_dir, name)
            check(os.path.isfile(path) and os.path.getsize(path) > 0, f"{name}: not written")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print(f"fixed_bed_quick: porosity {r['porosity']:.4f} ± {r['porosity_error']:.4f}, "
              f"volume check {v['found_over_summed']:.4f}, wall ring "
              f"{profile[-1]['porosity']:.3f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
