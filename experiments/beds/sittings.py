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


def run_sitting(argv, info, info_path, time_limit, driver, env=None):
    """Runs talus (a start or a resume: `argv`) for at most `time_limit` seconds (None: to the
    end). Adds the sitting to `info` (`sittings`, `run_wall_seconds`, `commands`) and writes it
    to `info_path`; `env` is the process's environment (None: this one's). Returns talus's
    summary (a dict) once the run has ended, None when the time limit stopped it with a
    checkpoint (the caller says how to go on); exits with the error for any other outcome."""
    if time_limit is not None:
        argv = argv + ["--stop-after", repr(float(time_limit))]
    started = time.monotonic()
    proc = subprocess.run(argv, capture_output=True, text=True, env=env)
    info["run_wall_seconds"] = info.get("run_wall_seconds", 0.0) + time.monotonic() - started
    info["sittings"] = info.get("sittings", 0) + 1
    info.setdefault("commands", []).append(" ".join(argv))
    if proc.returncode == STOPPED:
        info["finished"] = False
        write_atomically(info_path, json.dumps(info, indent=2) + "\n")
        last = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ""
        print(f"{driver}: stopped after {time_limit} s with a checkpoint ({last})")
        return None
    if proc.returncode != 0:
        sys.exit(f"{driver}: the run failed ({proc.returncode}): {' '.join(argv)}\n"
                 + proc.stderr[-3000:])
    summary = json.loads(proc.stdout)
    info["finished"] = True
    write_atomically(info_path, json.dumps(info, indent=2) + "\n")
    return summary
