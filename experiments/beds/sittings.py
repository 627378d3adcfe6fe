"""Runs of talus longer than one sitting, for the experiment drivers (fixed_bed.py, silo.py,
platonic_packing.py).

The GPU machine's calls last at most ten minutes, so a driver gives `talus run` a time limit
(`--stop-after S`: at the first step boundary after S seconds talus writes a checkpoint and exits
with status 75, EX_TEMPFAIL, "try again") and resumes the run in the next call (`talus run
--resume RUN/checkpoints`), which continues the uninterrupted run to the bit (docs/scenes.md,
checkpoints). The driver's record of the run (`run.json`) says how many sittings it took, their
commands and wall seconds, and whether it has ended.
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

# talus's exit status for a run that --stop-after stopped (solver/app/commands.hpp, kExitStopped).
STOPPED = 75


def write_atomically(path, data):
    """Writes `data` (text or bytes) to a temporary file beside `path`, then renames it: an
    interrupted driver leaves the old file or the new one, never half of one."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".")
    with os.fdopen(fd, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    os.replace(tmp, path)


def sitting_record(summary, wall):
    """A sitting's line in run.json's `sitting_steps`: the step it reached, its wall seconds, and
    from talus's summary (an ended or a stopped sitting's) the particles, the pair-list builds,
    the stage seconds, and the steps after the first with their seconds and stage seconds."""
    record = {"step": summary.get("steps"), "wall_seconds": wall}
    for key in ("particles", "pair_list_builds", "mean_contacts_per_step", "stage_seconds",
                "steady"):
        if key in summary:
            record[key] = summary[key]
    return record


def run_sitting(argv, info, info_path, time_limit, driver, env=None):
    """Runs talus (a start or a resume: `argv`) for at most `time_limit` seconds (None: to the
    end). talus's stderr streams into `sitting-<n>.log` beside `info_path` (the command on its
    first line), so that a sitting killed from outside leaves what talus said. Adds the sitting
    to `info` (`sittings`, `run_wall_seconds`, `commands`, `sitting_steps`: sitting_record) and
    writes it to `info_path`; `env` is the process's environment
    (None: this one's). Returns talus's summary (a dict) once the run has ended, None when the
    time limit stopped it with a checkpoint (the caller says how to go on); exits with the error
    for any other outcome."""
    if time_limit is not None:
        argv = argv + ["--stop-after", repr(float(time_limit))]
    sitting = info.get("sittings", 0) + 1
    log_path = os.path.join(os.path.dirname(os.path.abspath(info_path)), f"sitting-{sitting}.log")
    started = time.monotonic()
    with open(log_path, "w") as log:
        log.write(" ".join(argv) + "\n")
        log.flush()
        proc = subprocess.run(argv, stdout=subprocess.PIPE, stderr=log, text=True, env=env)
    wall = time.monotonic() - started
    with open(log_path) as log:
        stderr = log.read().split("\n", 1)[-1]
    info["run_wall_seconds"] = info.get("run_wall_seconds", 0.0) + wall
    info["sittings"] = sitting
    info.setdefault("commands", []).append(" ".join(argv))
    if proc.returncode == STOPPED:
        info["finished"] = False
        last = stderr.strip().splitlines()[-1] if stderr.strip() else ""
        try:  # talus writes the stopped sitting's summary too (marked "stopped")
            summary = json.loads(proc.stdout)
        except ValueError:
            reached = re.search(r" at step (\d+) ", last)
            summary = {"steps": int(reached.group(1)) if reached else None}
        info.setdefault("sitting_steps", []).append(sitting_record(summary, wall))
        write_atomically(info_path, json.dumps(info, indent=2) + "\n")
        print(f"{driver}: stopped after {time_limit} s with a checkpoint ({last})")
        return None
    if proc.returncode != 0:
        sys.exit(f"{driver}: the run failed ({proc.returncode}): {' '.join(argv)}\n"
                 + stderr[-3000:] + f"\n(talus's whole stderr: {log_path})")
    summary = json.loads(proc.stdout)
    info["finished"] = True
    info.setdefault("sitting_steps", []).append(sitting_record(summary, wall))
    write_atomically(info_path, json.dumps(info, indent=2) + "\n")
    return summary
