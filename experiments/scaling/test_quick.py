#!/usr/bin/python3
"""ctest `scaling_quick` (label parallel): the scaling driver's quick size on 1 and 2 ranks.

Runs run_scaling.py --quick --ranks 1 2 --settle-ranks 2 with the given talus, first with
--settle-sitting 1e-6 (the first settle stops at its step 0 with a checkpoint: exit status 4),
then with --settle-only (that settle goes on from the checkpoint, the other is settled, nothing
measured), then plainly with a copy of the binary (both settles reused: the same bytes), and checks its
scaling.json: each settle run on 2 ranks, the first in 2 sittings, both reused, every
(mode, ranks) run present with the particles its mode asks for, measured steps > 0, seconds per
step > 0, the exchange's share of the step in (0, 1) on 2 ranks and 0 on 1, no stage beside
another (the host step) so the stages a step are their sum and the rest what the step leaves
after them and the exchange, efficiency = speedup / ranks, and the figure and the table written. Skipped (exit 77) where mpirun or
/usr/bin/python3's matplotlib is missing, or talus was built without MPI (the driver's exit
status 3).

    test_quick.py TALUS WORK_DIR
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
    if shutil.which("mpirun") is None:
        print("SKIPPED: no mpirun (scripts/setup installs Open MPI)")
        return 77
    if importlib.util.find_spec("matplotlib") is None:  # the driver draws the figure with it
        print(f"SKIPPED: {sys.executable} has no matplotlib (Debian's python3-matplotlib)")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    out = os.path.join(work, "out")
    command = [sys.executable, os.path.join(HERE, "run_scaling.py"), "--talus", talus, "--quick",
               "--ranks", "1", "2", "--settle-ranks", "2", "--output", out,
               "--work", os.path.join(work, "runs")]
    proc = subprocess.run(command + ["--settle-sitting", "1e-6"], capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode == 3:
        print("SKIPPED: the driver cannot run here (above)")
        return 77
    if proc.returncode != 4 or "run the same command again" not in proc.stderr:
        print(f"scaling_quick: with --settle-sitting 1e-6, run_scaling.py exited with status "
              f"{proc.returncode}, not 4 with 'run the same command again'")
        return 1
    proc = subprocess.run(command + ["--settle-only"], capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 0 or os.path.exists(os.path.join(out, "scaling.json")):
        print(f"scaling_quick: with --settle-only, run_scaling.py exited with status "
              f"{proc.returncode} (expected 0) and wrote scaling.json: "
              f"{os.path.exists(os.path.join(out, 'scaling.json'))} (expected none)")
        return 1
    # The measured call with a copy of the binary: the same bytes at another path with a new
    # modification time (as the GPU machine unpacks its carried binary at each call) still find
    # the settles.
    copy = os.path.join(work, "talus-copy")
    shutil.copy(talus, copy)
    command[command.index(talus)] = copy
    proc = subprocess.run(command, capture_output=True, text=True)
    sys.stderr.write(proc.stderr)
    if proc.returncode != 0:
        print(f"scaling_quick: run_scaling.py exited with status {proc.returncode}")
        return 1
    with open(os.path.join(out, "scaling.json")) as f:
        result = json.load(f)
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    runs = {(r["mode"], r["ranks"]): r for r in result["runs"]}
    check(len(runs) == len(result["runs"]), "a (mode, ranks) run listed twice")
    for mode in ("weak", "strong"):
        for ranks in (1, 2):
            r = runs.get((mode, ranks))
            if r is None:
                failures.append(f"{mode} on {ranks} ranks: missing")
                continue
            name = f"{mode} on {ranks} ranks"
            want = result["per_rank"] * ranks if mode == "weak" else result["total"]
            check(r["particles"] == want, f"{name}: {r['particles']} particles, not {want}")
            check(r["measured_steps"] > 0, f"{name}: {r['measured_steps']} steps measured")
            check(r["seconds_per_step"] > 0, f"{name}: {r['seconds_per_step']} s a step")
            check(r["threads_per_rank"] == 1, f"{name}: {r['threads_per_rank']} threads a rank")
            share = r["exchange_share"]
            if ranks == 1:
                check(share == 0, f"{name}: exchange share {share}, not 0")
            else:
                check(0 < share < 1, f"{name}: exchange share {share}, not in (0, 1)")
            expected = r["speedup"] / ranks
            check(abs(r["efficiency"] - expected) <= 1e-12 * max(1.0, abs(expected)),
                  f"{name}: efficiency {r['efficiency']} is not speedup / ranks = {expected}")
            # The host step runs no stage beside another: the step's stage sum is every stage's,
            # and the rest is what the step's time leaves after it and the exchange.
            check(r["stages_beside"] == {}, f"{name}: stages beside {r['stages_beside']}")
            stages = sum(r["stage_seconds_per_step"].values())
            check(abs(r["stages_seconds_per_step"] - stages) <= 1e-12 * stages,
                  f"{name}: stages {r['stages_seconds_per_step']} a step, not their sum {stages}")
            rest = r["seconds_per_step"] - stages - r["exchange_seconds_per_step"]
            check(abs(r["rest_seconds_per_step"] - rest) <= 1e-12 * r["seconds_per_step"],
                  f"{name}: rest {r['rest_seconds_per_step']}, not {rest}")
            if ranks == 1:
                check(r["speedup"] == 1, f"{name}: speedup {r['speedup']} on one rank, not 1")
            check(r["command"] and "-np" in r["command"], f"{name}: no command recorded")
    for s in result["settles"]:
        # --settle-ranks 2: the settle ran under mpirun on 2 ranks (talus's summary said so).
        check(s.get("ranks") == 2 and "-np 2" in s["command"],
              f"the settle of {s['particles']}: ranks {s.get('ranks')}, command {s['command']}")
        check(s.get("reused") is True, f"the settle of {s['particles']} was not reused")
        check(s["mean_contacts_per_step"] > 0,
              f"the settle of {s['particles']}: {s['mean_contacts_per_step']} contacts a step")
    # The first count settled was stopped at step 0 and went on in a second sitting, resumed
    # to step S + 1 (--end) on 2 ranks; the others settled in one.
    sittings = sorted(s["sittings"] for s in result["settles"])
    check(sittings[-1] == 2 and sittings[:-1] == [1] * (len(sittings) - 1),
          f"settle sittings {sittings}: expected one settle in 2, the others in 1")
    for s in result["settles"]:
        if s["sittings"] == 2:
            check(len(s["continued_by"]) == 1 and "--resume" in s["continued_by"][0]
                  and "--end" in s["continued_by"][0] and "-np 2" in s["continued_by"][0],
                  f"the continued settle's commands: {s['continued_by']}")
    check(bool(result["machine"].get("cpu_model")), "no CPU model")
    check(bool(result.get("commit")), "no commit")
    for name in ("scaling.png", "results.md"):
        path = os.path.join(out, name)
        check(os.path.isfile(path) and os.path.getsize(path) > 0, f"{name}: not written")
    for f in failures:
        print(f"scaling_quick: {f}")
    if failures:
        return 1
    print(f"scaling_quick: {len(runs)} runs checked ({out}/scaling.json)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
