#!/usr/bin/python3
"""ctest `platonic_packing_quick`: the Platonic study's driver end to end at CI's size
(platonic_packing.py --quick: 128 cubes and 128 spheres, friction 0.4, poured and shaken two
cycles, on the host; stopped after 3 s and gone on with), its study.json checked.

    test_quick.py TALUS WORK_DIR

Checks, each a number that a broken driver, scene, wall motion or analysis gets wrong:
  - both cases ran, with all 128 particles and every step of the scene's time, the cubes in
    two sittings (stopped by --time-limit, then gone on with);
  - the random points find the particles' summed volume within 1 % + 4 sampling errors (the
    overlaps are far below 1 % of a particle's volume; a wrong rotation or inside test misses
    tens of percent);
  - the shaken box worked on the bed: the energy probe's wall work is positive and at least
    1e-5 J (128 particles of 0.2 to 0.6 g thrown at up to A 2 pi f = 0.08 m/s: about 1e-4 J);
  - each bed has a core, poured and tapped, and its packing fraction lies in [0.35, 0.75]
    (random packings of spheres 0.55 to 0.64, of cubes 0.5 to 0.7 in experiments and
    simulations; a bed this shallow, a little looser; a bed that did not form, or particles
    overlapping deeply, fall outside);
  - study.md and study.png are written.
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
    # Stopped after 3 s (a case takes 6 s or more here), then the same command again goes on
    # from the checkpoints: the path of a study longer than one of the GPU machine's calls.
    driver = [sys.executable, os.path.join(HERE, "platonic_packing.py"), "--talus", talus,
              "--quick", "--jobs", "2", "--output", work]
    proc = subprocess.run(driver + ["--time-limit", "3"], capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 3:
        print(f"platonic_packing.py --quick --time-limit 3 exited with {proc.returncode}, "
              "expected 3 (stopped with checkpoints)")
        return 1
    proc = subprocess.run(driver, capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 0:
        print(f"platonic_packing.py --quick exited with {proc.returncode}")
        return 1
    study = json.load(open(os.path.join(work, "study.json")))
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    shapes = sorted(c["shape"] for c in study["cases"])
    check(shapes == ["cube", "sphere"], f"cases {shapes}, expected cube and sphere")
    for c in study["cases"]:
        name = c["case"]
        check(c.get("particles") == 128, f"{name}: {c.get('particles')} particles, expected 128")
        # Every step of the scene's time, over its sittings: a resume from step 0, or one that
        # stopped early, gives another count.
        end = (study["size"]["pour"] + study["size"]["cycles"] / study["size"]["frequency"]
               + study["size"]["rest"])
        check(abs(c.get("steps", 0) - end / c["time_step_s"]) <= 1,
              f"{name}: {c.get('steps')} steps in {c.get('sittings')} sittings, expected "
              f"{end / c['time_step_s']:.0f}")
        v = c.get("volume_check") or {}
        check(v and abs(v["found_over_summed"] - 1) <= 0.01 + 4 * v["error"],
              f"{name}: the sampled solid volume over the summed volume: {v}")
        check((c.get("wall_work_J") or 0) >= 1e-5, f"{name}: wall work {c.get('wall_work_J')}")
        for protocol in ("poured", "tapped"):
            phi = (c.get(protocol) or {}).get("phi")
            check(phi is not None and 0.35 <= phi <= 0.75,
                  f"{name}, {protocol}: packing fraction {phi} outside [0.35, 0.75] "
                  f"(core height {(c.get(protocol) or {}).get('core_height_d')} d)")
    # The cubes (the slower case: 6 s or more here) were stopped by the limit and gone on with.
    sittings = {c["shape"]: c.get("sittings") for c in study["cases"]}
    check(sittings.get("cube") == 2, f"the cubes ran in {sittings.get('cube')} sittings, "
          "expected 2 (stopped after 3 s, then gone on with)")
    for name in ("study.md", "study.png"):
        path = os.path.join(work, name)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"{name}: not written")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print("platonic_packing_quick: " + "; ".join(
            f"{c['case']} poured {c['poured']['phi']:.3f}, tapped {c['tapped']['phi']:.3f}"
            for c in study["cases"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
