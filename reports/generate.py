#!/usr/bin/python3
"""The report generator: validation results and benchmark timings to one self-contained HTML page
(CSS inline, figures as base64 PNG) and its Markdown twin with the figures beside it.

It reads only result files: talus validate's validation-results.json (and each case's figure
beside it) and Google Benchmark's JSON output; reports/README.md says what it writes and how
provenance works. A bad input stops it before anything is written: one line naming the file,
exit status 2. matplotlib (Debian's) draws off screen (Agg).
"""
import argparse
import base64
import csv
import datetime
import html
import io
import json
import math
import os
import re
import sys
import tempfile

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
VALIDATION_KEYS = ("commit", "backend", "version", "passed", "cases", "results")
CASE_KEYS = ("case", "passed", "checks_passed", "checks_failed", "reported", "wall_seconds")
RESULT_KEYS = ("case", "quantity", "measured", "expected", "tolerance", "verdict")
# What Google Benchmark writes in every context and row; any other key is the program's own:
# custom context (--benchmark_context, AddCustomContext) or a user counter.
STANDARD_CONTEXT = {"date", "host_name", "executable", "num_cpus", "mhz_per_cpu",
                    "cpu_scaling_enabled", "caches", "load_avg", "library_build_type",
                    "library_version", "json_schema_version"}
STANDARD_ROW = {"name", "family_index", "per_family_instance_index", "run_name", "run_type",
                "repetitions", "repetition_index", "iterations", "real_time", "cpu_time",
                "time_unit", "label", "error_occurred", "error_message", "aggregate_name",
                "aggregate_unit", "threads"}
# The counters with a column of their own (benchmarks/*.cpp). A counter named `threads` (the host
# threads of bench_scenes and bench_step_cpu) repeats the row's own `threads` key; Google
# Benchmark writes counters last, so json keeps the counter, which is the number wanted.
RATE_KEYS = ("particle_steps_per_s", "particle_steps/s", "polyhedron_steps/s")
BYTES_KEYS = ("bytes_per_particle", "device_bytes_per_particle")
OWN_COLUMNS = {"steps_per_s", "particles", "threads"} | set(RATE_KEYS) | set(BYTES_KEYS)
# talus accuracy's CSV (experiments/accuracy/): its columns, the knobs and scenes it varies.
ACCURACY_COLUMNS = ("knob", "setting", "value", "scene", "metric", "reference", "error",
                    "wall_seconds", "simulated_seconds", "steps", "particles", "precision")
ACCURACY_NUMBERS = ("value", "error", "wall_seconds", "simulated_seconds", "steps", "particles")
KNOBS = ("contact_law", "shape_resolution", "wall_mesh", "precision", "time_step", "skin")
SCENES = ("impact", "packing", "drum")
# bench_effects' rows: effects/<backend>/all and effects/<backend>/without_<effect>, with Google
# Benchmark's suffixes: those of how it was timed are dropped (/iterations:300/manual_time), any
# other (/threads:2) becomes part of the backend's column.
EFFECT_NAME = re.compile(r"^effects/(?P<backend>[^/]+)/(?:all|without_(?P<effect>[^/]+))"
                         r"(?:/(?P<rest>.+))?$")
TIMING_SUFFIX = re.compile(r"^(iterations:\d+|repeats:\d+|(min_|min_warmup_)time:[^/]*|"
                           r"manual_time|real_time|process_time)$")


class Refusal(Exception):
    """A bad input or an output that cannot be written: the one line printed before exit 2."""


def fmt(value):
    """4 significant figures; whole numbers exactly, both with thousands separators."""
    if value is None:
        return "—"
    if not is_number(value) or not math.isfinite(value):
        return str(value)
    if float(value).is_integer() and abs(value) < 1e9:
        return f"{int(value):,}"
    if 1e3 <= abs(value) < 1e12:
        return f"{float(f'{value:.4g}'):,.0f}"
    mantissa, _, exponent = f"{value:.4g}".partition("e")
    return mantissa + (f"e{int(exponent)}" if exponent else "")


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except UnicodeDecodeError:
        raise Refusal(f"{path}: not JSON (not UTF-8 text)")
    except json.JSONDecodeError as e:
        raise Refusal(f"{path}: not JSON ({e.msg} at line {e.lineno}, column {e.colno})")
    except OSError as e:
        raise Refusal(f"{path}: cannot be read ({e.strerror})")


def require(obj, keys, path, where, what, lists=(), numbers=()):
    """`obj` is an object with `keys`, those of `lists` lists and those of `numbers` numbers
    (or null, which is what the C++ writes for a NaN); else a Refusal naming file and key."""
    if not isinstance(obj, dict):
        raise Refusal(f"{path}: {where} is not a JSON object; expected {what}")
    for key in keys:
        if key not in obj:
            raise Refusal(f"{path}: {where} has no key '{key}'; expected {what}")
        if (key in lists and not isinstance(obj[key], list)) or (
                key in numbers and obj[key] is not None and not is_number(obj[key])):
            kind = "a list" if key in lists else "a number"
            raise Refusal(f"{path}: {where}'s '{key}' is not {kind}; expected {what}")


def read_validation(path):
    what = "talus validate's validation-results.json"
    data = load_json(path)
    require(data, VALIDATION_KEYS, path, "the top level", what, lists=("cases", "results"))
    for i, case in enumerate(data["cases"]):
        require(case, CASE_KEYS, path, f"cases[{i}]", what, numbers=CASE_KEYS[2:])
    for i, row in enumerate(data["results"]):
        require(row, RESULT_KEYS, path, f"results[{i}]", what, numbers=RESULT_KEYS[2:5])
    return data


def read_benchmark(path):
    what = "Google Benchmark's JSON (--benchmark_out_format=json)"
    data = load_json(path)
    require(data, ("context", "benchmarks"), path, "the top level", what, lists=("benchmarks",))
    require(data["context"], (), path, "'context'", what)
    for i, row in enumerate(data["benchmarks"]):
        require(row, ("name",), path, f"benchmarks[{i}]", what)
        if not row.get("error_occurred"):  # a skipped benchmark has no times
            require(row, ("real_time", "time_unit"), path, f"benchmarks[{i}]", what,
                    numbers=("real_time",))
    return data


def read_provenance(path):
    data = load_json(path) if path else {}
    require(data, (), path, "the top level", "an object of file name to provenance")
    for name, entry in data.items():
        require(entry, (), path, f"'{name}'", "an object with machine, command, commit")
    return data


def provenance_entry(provenance, path):
    """The provenance given for an input: by the path as given, else by its file name (every
    validation file is called validation-results.json, so the path may be needed)."""
    return provenance.get(path) or provenance.get(os.path.basename(path)) or {}


def merged(own, given):
    """What the file records, checked against what the provenance file says."""
    if own and given and str(own) != str(given):
        return f"{own} (the provenance file says {given})"
    return str(own or given or "not recorded")


def source(sid, kind, path, given, machine=None, commit=None, command=None, date=None,
           recorded="—"):
    """A provenance row: what the file records joined with what the provenance file gives."""
    return {"id": sid, "kind": kind, "file": path, "recorded": recorded,
            "machine": ", ".join(str(x) for x in (given.get("machine"), machine) if x)
            or "not recorded",
            "commit": merged(commit, given.get("commit")),
            "command": str(given.get("command") or command or "not recorded"),
            "date": merged(date, given.get("date")), "polyhedra": bool(given.get("polyhedra"))}


def validation_source(sid, path, data, given):
    return source(sid, "validation", path, given, commit=data["commit"],
                  recorded=f"backend {data['backend']}, {data['version']} versions")


def benchmark_source(sid, path, data, given):
    context = data["context"]
    host = context.get("host_name")
    if host:
        host = f"host {host}, {context.get('num_cpus', '?')} CPUs"
        host += f" at {context['mhz_per_cpu']} MHz" if context.get("mhz_per_cpu") else ""
    machine = ", ".join(str(x) for x in (host, context.get("gpu")) if x)
    command = context.get("executable")
    custom = {k: v for k, v in context.items() if k not in STANDARD_CONTEXT}
    recorded = [f"{k} {v}" for k, v in custom.items() if k not in ("commit", "gpu")]
    if context.get("library_build_type"):
        recorded.insert(0, f"library built as {context['library_build_type']}")
    return source(sid, "benchmark", path, given, machine, custom.get("commit"),
                  command and f"{command} (its arguments not recorded)", context.get("date"),
                  "; ".join(recorded) or "—")


class Table:
    """Headers and rows of cells, each row with whether it is a failure (red, bold)."""
    def __init__(self, headers):
        self.headers, self.rows = headers, []

    def add(self, cells, failed=False):
        self.rows.append(([str(c) for c in cells], failed))


def provenance_blocks(sources):
    table = Table(["source", "kind", "file", "machine", "commit", "command", "date",
                   "also recorded"])
    for s in sources:
        table.add([s["id"], s["kind"], s["file"], s["machine"], s["commit"], s["command"],
                   s["date"], s["recorded"]])
    note = ("Every table below names its source; the machine, commit and command behind each "
            "number are in this row. \"not recorded\": neither the file nor a provenance file "
            "says.")
    return [("h2", "Provenance"), ("p", note), ("table", table)]


def summary_blocks(validations):
    table = Table(["source", "case", "result", "checks passed", "failed", "reported",
                   "backend", "wall time", "commit"])
    notes, verdicts = [], {}
    for source, data in validations:
        for case in data["cases"]:
            result = ("pass" if case["passed"] else "FAIL") + (
                f": {case['failure']}" if case.get("failure") else "")  # it could not run
            table.add([source["id"], case["case"], result,
                       fmt(case["checks_passed"]), fmt(case["checks_failed"]),
                       fmt(case["reported"]), case.get("backend", data["backend"]),
                       fmt(case["wall_seconds"]) + " s", data["commit"]],
                      failed=not case["passed"])
            rows = [r for r in data["results"] if r["case"] == case["case"]]
            counted = [sum(r["verdict"] == v for r in rows) for v in ("pass", "fail", "reported")]
            if counted != [case["checks_passed"], case["checks_failed"], case["reported"]]:
                notes.append(f"{source['id']} {case['case']}: its rows count {counted} passed, "
                             "failed and reported, not what its summary says.")
        verdict = "every case passes" if data["passed"] else "a case FAILS"
        verdicts.setdefault(f"{verdict} ({data['version']} versions, backend "
                            f"{data['backend']}, commit {data['commit']}).", []).append(
                                source["id"])
    # One line per verdict: the nightly's one file per case would repeat it for every file.
    notes += [f"{', '.join(ids)}: {text}" for text, ids in verdicts.items()]
    return [("h2", "Validation summary"), ("table", table), ("list", notes)]


def error_ratio(row):
    """|measured - expected| / tolerance, run_validation.cpp's measure of the worst row."""
    if row["measured"] is None or row["expected"] is None:
        return math.inf  # a NaN measured: as bad as can be
    if not row["tolerance"]:
        return math.inf if row["measured"] != row["expected"] else 0.0
    return abs(row["measured"] - row["expected"]) / row["tolerance"]


def quantity_key(row):
    return (row["quantity"], row.get("variant", ""))


def summarised(rows):
    """Of a large case's rows: every failed one and each quantity's worst checked one; a
    quantity with only reported rows is kept when it has one row. Also the quantities left out."""
    groups = {}
    for row in rows:
        groups.setdefault(quantity_key(row), []).append(row)
    keep, left_out = set(), []
    for key, group in groups.items():
        checked = [r for r in group if r["verdict"] != "reported"]
        keep.update(id(r) for r in checked if r["verdict"] == "fail")
        if checked:
            keep.add(id(max(checked, key=error_ratio)))
        elif len(group) == 1:
            keep.add(id(group[0]))
        else:
            left_out.append(f"{' '.join(k for k in key if k)} ({len(group)} reported rows)")
    return [r for r in rows if id(r) in keep], left_out


def check_cells(source, row, show_parameter):
    unit = row.get("unit", "")
    quantity = row["quantity"] + (f" ({unit})" if unit and unit != "1" else "")
    setting = row.get("variant", "")
    if show_parameter:
        setting = f"{setting} at {fmt(row.get('parameter'))}".strip()
    reported = row["verdict"] == "reported"
    tolerance = "—" if reported and not row["tolerance"] else fmt(row["tolerance"])
    verdict = {"pass": "pass", "fail": "FAIL"}.get(row["verdict"], row["verdict"])
    return [source["id"], row["case"], quantity, setting or "—", fmt(row["measured"]),
            fmt(row["expected"]), tolerance, verdict]


def checks_blocks(validations, max_rows):
    """One table per case, headed by its counts; on the page a case's table is folded away
    (a click opens it) unless one of its rows failed."""
    blocks = [("h2", "Checks"), ("p", "Failed rows are marked FAIL (red on the HTML page). "
                                      "Tolerances are absolute bounds on |measured - expected|; "
                                      "reported rows are measured, never failed. On the page a "
                                      "case's rows are folded away unless one failed.")]
    for source, data in validations:
        for case in data["cases"]:
            table = Table(["source", "case", "quantity", "variant / parameter", "measured",
                           "expected", "tolerance", "verdict"])
            rows = [r for r in data["results"] if r["case"] == case["case"]]
            shown, note = rows, ""
            if len(rows) > max_rows:
                shown, left_out = summarised(rows)
                note = (f"{len(rows):,} rows summarised as {len(shown)}: every failed row and "
                        "the worst checked row (largest |measured - expected| / tolerance) of "
                        "each quantity")
                if left_out:
                    note += "; not shown: " + ", ".join(left_out)
            counts = {}
            for r in rows:
                counts[quantity_key(r)] = counts.get(quantity_key(r), 0) + 1
            for r in shown:
                show_parameter = counts[quantity_key(r)] > 1 or r.get("parameter")
                table.add(check_cells(source, r, show_parameter), failed=r["verdict"] == "fail")
            verdicts = [sum(r["verdict"] == v for r in rows) for v in ("pass", "fail")]
            heading = (f"{source['id']} {case['case']}: {verdicts[0]:,} passed, "
                       f"{verdicts[1]:,} failed, {len(rows) - sum(verdicts):,} reported"
                       + (f" ({note})" if note else ""))
            if rows:
                blocks.append(("table", table, {"fold": heading, "open": verdicts[1] > 0}))
            else:
                blocks.append(("p", heading + ": no rows."))
    return blocks


def figure_blocks(validations, figures):
    """Each case's own figure, read from beside its validation-results.json, and its notes."""
    blocks = []
    for source, data in validations:
        folder = os.path.dirname(os.path.abspath(source["file"]))
        for case in data["cases"]:
            blocks.append(("h3", f"{source['id']} {case['case']}: {case.get('title', '')}"))
            blocks.append(("list", [str(n) for n in case.get("notes") or []]))
            if not case.get("figure"):
                continue
            path = os.path.join(folder, case["figure"])
            try:
                with open(path, "rb") as f:
                    png = f.read()
            except OSError:
                png = b""
            if not png.startswith(PNG_MAGIC):
                blocks.append(("p", f"Its figure {case['figure']} is not beside the file."))
                continue
            name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{source['id']}-{case['case']}") + ".png"
            figures[name] = png
            blocks.append(("figure", name, f"{case['case']} ({source['id']}): the case's "
                                           "figure, as talus validate drew it"))
    return [("h2", "Case figures and notes")] + blocks if blocks else []


def chosen_rows(data):
    """Per run name: its one iteration row; with repetitions the median aggregate (else the
    mean); with neither, every iteration row. Standard deviations and CVs are left out."""
    groups = {}
    for row in data["benchmarks"]:
        groups.setdefault(row.get("run_name", row["name"]), []).append(row)
    chosen = []
    for name, rows in groups.items():
        runs = [r for r in rows if r.get("run_type", "iteration") == "iteration"]
        aggregates = {r.get("aggregate_name"): r for r in rows if r.get("run_type") == "aggregate"}
        pick = aggregates.get("median") or aggregates.get("mean")
        if len(runs) == 1:
            chosen.append((name, runs[0]))
        elif pick:
            how = pick["aggregate_name"]
            chosen.append((f"{name} ({how} of {pick.get('repetitions', len(runs))})", pick))
        else:
            chosen += [(f"{name} #{r.get('repetition_index', k)}", r) for k, r in enumerate(runs)]
    return chosen


def rate(row):
    """(particle-steps/s, whether the counter says polyhedra) or (None, False)."""
    for key in RATE_KEYS:
        if is_number(row.get(key)):
            return row[key], key.startswith("polyhedron")
    return None, False


def speed_blocks(benchmarks, figures):
    rows = [(s, name, r) for s, data in benchmarks for name, r in chosen_rows(data)]
    polyhedra = [s["polyhedra"] or rate(r)[1] for s, _, r in rows if rate(r)[0] is not None]
    rate_name = "polyhedron-steps/s" if polyhedra and all(polyhedra) else "particle-steps/s"
    table = Table(["source", "benchmark", "time an iteration", "steps/s", rate_name,
                   "particles", "bytes a particle", "threads", "other counters"])
    bars = []
    for source, name, row in rows:
        if row.get("error_occurred"):
            table.add([source["id"], name, "skipped: " + str(row.get("error_message", ""))]
                      + ["—"] * 6, failed=True)
            continue
        steps, poly = rate(row)
        cell = fmt(steps)
        if steps is not None and (poly or source["polyhedra"]) and not all(polyhedra):
            cell += " (polyhedra)"
        per_particle = next((row[k] for k in BYTES_KEYS if k in row), None)
        others = [f"{k} {fmt(v)}" for k, v in row.items() if k not in STANDARD_ROW
                  and k not in OWN_COLUMNS and is_number(v)]
        others = [f"cpu {fmt(row.get('cpu_time'))} {row['time_unit']}",
                  f"iterations {fmt(row.get('iterations'))}"] + others
        table.add([source["id"], name, f"{fmt(row['real_time'])} {row['time_unit']}",
                   fmt(row.get("steps_per_s")), cell, fmt(row.get("particles")),
                   fmt(per_particle), fmt(row.get("threads")), "; ".join(others)])
        if steps is not None and steps > 0:
            bars.append((f"{source['id']} {name}", steps))
    note = ("Time an iteration is wall time (real_time); one row per benchmark, the median where "
            "it was repeated. polyhedron-steps/s where the counter (polyhedron_steps/s) or the "
            "provenance file (\"polyhedra\": true) says the particles were polyhedra.")
    blocks = [("h2", "Speed"), ("p", note), ("table", table)]
    if bars:
        figures["speed.png"] = bar_chart(bars, rate_name)
        blocks.append(("figure", "speed.png", f"{rate_name} of each benchmark that counts it"))
    return blocks


def pyplot(what):
    """matplotlib's pyplot drawing off screen, imported only where there is something to draw."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise Refusal(f"matplotlib is needed for {what} (Debian's python3-matplotlib)")
    return plt


def png_of(fig, plt):
    out = io.BytesIO()
    fig.savefig(out, format="png", dpi=120)
    plt.close(fig)
    return out.getvalue()


def bar_chart(bars, rate_name):
    plt = pyplot("the speed figure")
    labels, values = zip(*reversed(bars))  # the table's first row at the top
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.4 * len(bars)))
    ax.barh(range(len(bars)), values, color="C0", tick_label=labels)
    ax.tick_params(axis="y", labelsize=8)
    spans_decades = max(values) > 100 * min(values)  # the host's and a GPU's rates, say
    ax.set_xscale("log" if spans_decades else "linear")
    ax.set_xlim(min(values) / 3 if spans_decades else 0,  # the smallest bar shows
                max(values) * (3 if spans_decades else 1.25))  # room for the labels
    for k, v in enumerate(values):
        ax.text(v, k, " " + fmt(v), va="center", fontsize=8)
    ax.set_xlabel(rate_name)
    ax.set_title(f"{rate_name} (source and benchmark name on the left)", fontsize=10)
    fig.tight_layout()
    return png_of(fig, plt)


# --- The accuracy-against-time study (talus accuracy's CSV) -------------------------------------

def finite(value):
    return is_number(value) and math.isfinite(value)


def read_accuracy(path):
    """talus accuracy's CSV: leading `# key: value` lines (machine, commit, command, date,
    backend), then a header and one row per run. Every bad line is refused with its number."""
    what = ("talus accuracy's CSV: '# key: value' lines, then the header "
            + ",".join(ACCURACY_COLUMNS))
    try:
        with open(path, encoding="utf-8", newline="") as f:
            lines = f.read().splitlines()
    except UnicodeDecodeError:
        raise Refusal(f"{path}: not UTF-8 text; expected {what}")
    except OSError as e:
        raise Refusal(f"{path}: cannot be read ({e.strerror})")
    meta, header, rows = {}, None, []
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        if line.startswith("#"):
            key, colon, value = line[1:].partition(":")
            if header is None and colon:
                meta[key.strip()] = value.strip()
            continue
        cells = [c.strip() for c in next(csv.reader([line]))]
        where = f"{path}:{number}"
        if header is None:
            missing = [c for c in ACCURACY_COLUMNS if c not in cells]
            if missing:
                raise Refusal(f"{where}: the header has no column '{missing[0]}'; expected {what}")
            header = cells
            continue
        if len(cells) != len(header):
            raise Refusal(f"{where}: {len(cells)} fields where the header has {len(header)}; "
                          f"expected {what}")
        row = dict(zip(header, cells))
        for key in ACCURACY_NUMBERS:
            try:
                row[key] = float(row[key])
            except ValueError:
                raise Refusal(f"{where}: column '{key}' is '{row[key]}', not a number; "
                              f"expected {what}")
            # error and wall_seconds are nan for a setting talus accuracy listed but did not run
            # (more steps than the study allows): drawn nowhere, listed in the table.
            if key == "error" and math.isnan(row[key]) or \
                    key == "wall_seconds" and math.isnan(row[key]) and math.isnan(row["error"]):
                continue
            if key != "error" and not (math.isfinite(row[key]) and row[key] >= 0):
                raise Refusal(f"{where}: column '{key}' is {row[key]}; expected a finite "
                              "number >= 0")
        if row["knob"] not in KNOBS:
            raise Refusal(f"{where}: knob '{row['knob']}'; expected one of {', '.join(KNOBS)}")
        if row["scene"] not in SCENES:
            raise Refusal(f"{where}: scene '{row['scene']}'; expected one of {', '.join(SCENES)}")
        if row["error"] < 0:  # nan passes: a row whose error cannot be measured
            raise Refusal(f"{where}: error {row['error']}; expected a relative error >= 0 "
                          "or nan")
        row["line"] = number
        rows.append(row)
    if header is None:
        raise Refusal(f"{path}: no header row; expected {what}")
    return {"meta": meta, "rows": rows}


def accuracy_source(sid, path, data, given):
    meta = data["meta"]
    recorded = [f"backend {meta.get('backend', 'not recorded')}", f"{len(data['rows'])} rows"]
    recorded += [f"{k} {v}" for k, v in meta.items()
                 if k not in ("machine", "commit", "command", "date", "backend")]
    row = source(sid, "accuracy", path, given, meta.get("machine"), meta.get("commit"),
                 meta.get("command"), meta.get("date"), "; ".join(recorded))
    row["backend"] = meta.get("backend", "not recorded")
    return row


def cost(row):
    """Wall time per simulated second; nan where nothing was simulated."""
    return row["wall_seconds"] / row["simulated_seconds"] if row["simulated_seconds"] > 0 \
        else math.nan


def measurable(row):
    return math.isfinite(row["error"]) and math.isfinite(cost(row)) and cost(row) > 0


def pareto_status(rows):
    """id(row) -> "front" or "dominated" among the measurable rows given (one scene's): a row is
    dominated when another is at least as good in error and in cost and better in one."""
    points = [(r["error"], cost(r), r) for r in rows if measurable(r)]
    status = {}
    for e, c, r in points:
        dominated = any(e2 <= e and c2 <= c and (e2 < e or c2 < c) for e2, c2, _ in points)
        status[id(r)] = "dominated" if dominated else "front"
    return status


def scene_backends(rows):
    """The (scene, backend) pairs present, scenes in SCENES' order: errors and costs are
    compared within one scene on one backend, never across."""
    return [(s, b) for s in SCENES for b in sorted({r["backend"] for r in rows})
            if any(r["scene"] == s and r["backend"] == b for r in rows)]


def setting_name(row):
    return f"{row['knob']} '{row['setting']}'"


def accuracy_summary(rows, status):
    """The "best/worst accuracy per time" lines: per scene the front's lowest error x cost and
    the dominated setting's highest; the knob whose settings span the widest error range."""
    lines = []
    for scene, backend in scene_backends(rows):
        scene_rows = [r for r in rows if r["scene"] == scene and r["backend"] == backend
                      and id(r) in status]
        if not scene_rows:
            continue
        front = [r for r in scene_rows if status[id(r)] == "front"]
        dominated = [r for r in scene_rows if status[id(r)] == "dominated"]
        best = min(front, key=lambda r: (r["error"] * cost(r), cost(r)))
        line = (f"{scene} ({backend}): best accuracy per time {setting_name(best)} (error "
                f"{fmt(best['error'])} at {fmt(cost(best))} s a simulated s, on the Pareto "
                "front); ")
        inexact = [r for r in front if r["error"] > 0]
        if best["error"] == 0 and inexact:
            # A setting that gives its reference's very answer (a skin, say) has error x cost
            # 0 at any cost: the best of those that change the answer says more.
            runner_up = min(inexact, key=lambda r: r["error"] * cost(r))
            line += (f"of the settings that change the answer, {setting_name(runner_up)} "
                     f"(error {fmt(runner_up['error'])} at {fmt(cost(runner_up))} s); ")
        if dominated:
            worst = max(dominated, key=lambda r: r["error"] * cost(r))
            line += (f"worst {setting_name(worst)} (error {fmt(worst['error'])} at "
                     f"{fmt(cost(worst))} s a simulated s, dominated).")
        else:
            line += "no setting is dominated."
        lines.append(line)
    spans = []  # (factor, knob, scene, lowest, highest)
    for knob in KNOBS:
        for scene in SCENES:
            errors = [r["error"] for r in rows if r["knob"] == knob and r["scene"] == scene
                      and math.isfinite(r["error"]) and r["error"] > 0]
            if len(errors) > 1:
                spans.append((max(errors) / min(errors), knob, scene, min(errors), max(errors)))
    if spans:
        factor, knob, scene, low, high = max(spans)
        lines.append(f"Widest error range: {knob} ({scene}: error from {fmt(low)} to "
                     f"{fmt(high)} across its settings, a factor {fmt(factor)}).")
    return lines


def accuracy_blocks(accuracies, figures):
    rows = [(s, r) for s, data in accuracies for r in data["rows"]]
    for s, r in rows:
        r["backend"] = s["backend"]
    status = {}
    for scene, backend in scene_backends([r for _, r in rows]):
        status.update(pareto_status([r for _, r in rows
                                     if r["scene"] == scene and r["backend"] == backend]))
    order = {k: i for i, k in enumerate(KNOBS)}
    rows.sort(key=lambda sr: (order[sr[1]["knob"]], sr[1]["scene"], sr[1]["value"]))
    table = Table(["source", "knob", "setting", "scene", "error", "error of (against)",
                   "wall s per simulated s", "particles", "backend", "Pareto"])
    for s, r in rows:
        table.add([s["id"], r["knob"], r["setting"], r["scene"], fmt(r["error"]),
                   f"{r['metric']} (against {r['reference']})", fmt(cost(r)),
                   fmt(r["particles"]), s["backend"],
                   status.get(id(r), "not drawn: error nan" if math.isnan(r["error"])
                              else "not drawn: no simulated time")])
    note = ("Each row is one run of the study: its relative error against the reference named, "
            "and its cost, wall time per simulated second. Pareto: on the front of its scene "
            "and backend (no other run of the scene on that backend, of any knob, has both a "
            "lower or equal error and a lower or equal cost) or dominated. A row whose error is nan (the reference "
            "itself) is listed and not drawn.")
    blocks = [("h2", "Accuracy against time"), ("p", note),
              ("list", accuracy_summary([r for _, r in rows], status)), ("table", table)]
    drawn = [r for _, r in rows if measurable(r) and r["error"] > 0]
    zero = len([r for _, r in rows if measurable(r) and r["error"] == 0])
    if zero:
        blocks.append(("p", f"Not drawn (log axes): {zero} row{'s' * (zero > 1)} of error 0."))
    for knob in KNOBS:
        points = [r for r in drawn if r["knob"] == knob]
        if points:
            name = f"accuracy-{knob}.png"
            figures[name] = knob_chart(knob, points)
            blocks.append(("figure", name, f"{knob}: error against wall time per simulated "
                                           "second, each point labelled with its setting"))
    if drawn:
        figures["accuracy-pareto.png"] = pareto_chart(drawn, status)
        blocks.append(("figure", "accuracy-pareto.png",
                       "every knob's runs; the line joins each scene's Pareto front (runs no "
                       "other run of the scene beats in both error and cost)"))
    return blocks


def plain_log_labels(ax):
    """Log axes labelled as the tables write numbers (0.02, not 2 x 10^-2), with a grid."""
    from matplotlib.ticker import FuncFormatter

    def minor(axis):  # every minor tick within a decade, 2, 3 and 5 within two, else none
        def label(v, _):
            low, high = sorted(axis.get_view_interval())
            lead = round(v / 10 ** math.floor(math.log10(v) + 1e-9)) if v > 0 else 0
            shown = low > 0 and (high / low < 10 or (high / low < 100 and lead in (2, 3, 5)))
            return fmt(float(f"{v:.3g}")) if shown else ""
        return FuncFormatter(label)

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(FuncFormatter(lambda v, _: fmt(float(f"{v:.3g}"))))
        axis.set_minor_formatter(minor(axis))
    ax.grid(True, which="both", linewidth=0.3)


SCENE_STYLE = {"impact": ("o", "C0", "-"), "packing": ("s", "C1", "--"),
               "drum": ("^", "C2", ":")}


def knob_chart(knob, rows):
    plt = pyplot("the accuracy figures")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    pairs = scene_backends(rows)
    several = len({b for _, b in pairs}) > 1  # then the host's series are drawn hollow
    for scene, backend in pairs:
        points = sorted((r for r in rows if r["scene"] == scene and r["backend"] == backend),
                        key=lambda r: r["value"])
        marker, colour, _ = SCENE_STYLE[scene]
        ordered = len({r["value"] for r in points}) == len(points)  # else no order to join
        hollow = several and backend == "cpu"
        ax.plot([cost(r) for r in points], [r["error"] for r in points], marker=marker,
                color=colour, linestyle="-" if ordered else "none", linewidth=0.6,
                markerfacecolor="none" if hollow else colour,
                label=f"{scene} ({backend})" if several else scene)
        for r in points:
            ax.annotate(r["setting"], (cost(r), r["error"]), textcoords="offset points",
                        xytext=(4, 4), fontsize=7, color=colour)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.margins(0.15)
    ax.set_xlabel("wall time per simulated second (s)")
    ax.set_ylabel("relative error")
    ax.set_title(f"{knob}: error against cost (settings joined in the order of their value)",
                 fontsize=10)
    plain_log_labels(ax)
    ax.legend(fontsize=8, title="scene", title_fontsize=8)
    fig.tight_layout()
    return png_of(fig, plt)


def pareto_chart(rows, status):
    plt = pyplot("the accuracy figures")
    fig, ax = plt.subplots(figsize=(10.5, 6))
    knobs = [k for k in KNOBS if any(r["knob"] == k for r in rows)]
    colours = {k: f"C{i + 3}" for i, k in enumerate(knobs)}
    for r in rows:
        ax.plot(cost(r), r["error"], marker=SCENE_STYLE[r["scene"]][0], color=colours[r["knob"]],
                linestyle="none", alpha=1.0 if status.get(id(r)) == "front" else 0.45)
    for scene in SCENES:
        front = sorted((r for r in rows if r["scene"] == scene
                        and status.get(id(r)) == "front"), key=cost)
        if not front:
            continue
        ax.plot([cost(r) for r in front], [r["error"] for r in front], color="black",
                linestyle=SCENE_STYLE[scene][2], linewidth=1, drawstyle="steps-post")
        for r in front:
            ax.annotate(f"{r['knob']}: {r['setting']}", (cost(r), r["error"]),
                        textcoords="offset points", xytext=(4, -10), fontsize=7)
    handles = [plt.Line2D([], [], color=colours[k], marker="o", linestyle="none", label=k)
               for k in knobs]
    handles += [plt.Line2D([], [], color="black", marker=SCENE_STYLE[s][0],
                           linestyle=SCENE_STYLE[s][2], label=f"{s} (front)")
                for s in SCENES if any(r["scene"] == s for r in rows)]
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.margins(0.15)
    ax.set_xlabel("wall time per simulated second (s)")
    ax.set_ylabel("relative error")
    ax.set_title("Every knob's runs; dominated runs pale, the fronts joined", fontsize=10)
    plain_log_labels(ax)
    fig.tight_layout()
    return png_of(fig, plt)


# --- The effect-cost table (bench_effects: effects/<backend>/all and .../without_<effect>) ------

def effect_blocks(benchmarks):
    """Per effect, per backend and source file (one machine's run): ms a step with every effect,
    without it, and the difference. Files are never mixed: two machines' steps differ."""
    times, effects = {}, []
    for s, data in benchmarks:
        for _, row in chosen_rows(data):
            match = EFFECT_NAME.match(row.get("run_name") or row["name"])
            if not match:
                continue
            rest = "/".join(part for part in (match["rest"] or "").split("/")
                            if part and not TIMING_SUFFIX.match(part))
            backend = match["backend"] + (f" ({rest})" if rest else "")
            variant = match["effect"] or "all"
            if variant != "all" and variant not in effects:
                effects.append(variant)
            ms = row.get("ms_per_step")
            times.setdefault(f"{backend} ({s['id']})", {})[variant] = (
                "skipped" if row.get("error_occurred") else ms if finite(ms) else None)
    if not times:
        return []
    headers = ["effect"]
    for tag in times:
        headers += [f"{tag}: all, ms a step", "without it", "its cost, ms",
                    "its cost, % of all"]
    table = Table(headers)
    for effect in effects:
        cells = [effect]
        for variants in times.values():
            every, without = variants.get("all"), variants.get(effect)
            cells += [fmt(every) if every != "skipped" else "skipped",
                      fmt(without) if without != "skipped" else "skipped"]
            if finite(every) and finite(without):
                cells += [fmt(every - without),
                          fmt(100 * (every - without) / every) + " %" if every else "—"]
            else:
                cells += ["—", "—"]
        table.add(cells)
    note = ("From the benchmarks named effects/<backend>/all and effects/<backend>/without_"
            "<effect> (their counter ms_per_step, the median where repeated): an effect's cost "
            "is the step with every effect less the step without it. A cost within a few per "
            "cent of zero, or below it, is within the benchmark's noise.")
    return [("h2", "What each effect costs"), ("p", note), ("table", table)]


# --- History: the night's numbers, the earlier nights', and what regressed ----------------------

# The noise bands beyond which a number is flagged as regressed. Speed (a benchmark's time an
# iteration, the accuracy study's wall time per simulated second, a long case's wall time): 10 %
# slower. The nights run on whichever GPU machine of a kind comes, and machines of one kind
# differ by a few per cent, up to 10 % (benchmarks/README.md, "Hardware"); within one machine
# the GPU step repeats to 0.3 % (6.43-6.45 ms). A band of 10 % stays clear of the spread between
# machines and still catches a change that matters (the renumbering by cell was worth 5.5 %, a
# slower law 4 %: those show over a few nights against the median, not in one). The comparison is
# with the median of the last BASELINE_NIGHTS earlier nights of the same machine name, so one
# noisy night neither raises a flag nor hides one.
SPEED_BAND = 0.10
# Accuracy: an error up by more than 10 % of itself and by more than 1e-12. The study's errors
# are deterministic on one machine and build; 10 % leaves room for the order of float sums
# changing with the thread count or the GPU's atomics, and 1e-12 keeps round-off-level errors
# (the reference comparisons at 1e-14) from flagging on their last digits.
ERROR_BAND = 0.10
ERROR_FLOOR = 1e-12
# A validation case's wall time is flagged like speed only where it took this long on both
# nights: a small case's second is mostly the process starting and matplotlib drawing.
WALL_MIN_SECONDS = 10.0
BASELINE_NIGHTS = 5
HISTORY_SHOWN = 30  # the nights drawn: the last 30 of this machine
HISTORY_KEYS = ("date", "commit", "machine", "numbers")
TIME_UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def read_history(path, missing_ok=False):
    """The nights of a JSON-lines history file, each with its line number."""
    what = 'one JSON object a line: {"date", "commit", "machine", "numbers": {name: number}}'
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except FileNotFoundError:
        if missing_ok:
            return [], ""
        raise Refusal(f"{path}: cannot be read (No such file or directory)")
    except UnicodeDecodeError:
        raise Refusal(f"{path}: not UTF-8 text; expected {what}")
    except OSError as e:
        raise Refusal(f"{path}: cannot be read ({e.strerror})")
    nights = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            night = json.loads(line)
        except json.JSONDecodeError as e:
            raise Refusal(f"{path}:{number}: not JSON ({e.msg}, column {e.colno}); "
                          f"expected {what}")
        if not isinstance(night, dict) or any(k not in night for k in HISTORY_KEYS):
            raise Refusal(f"{path}:{number}: not an object with date, commit, machine and "
                          f"numbers; expected {what}")
        if not isinstance(night["numbers"], dict) or any(
                v is not None and not is_number(v) for v in night["numbers"].values()):
            raise Refusal(f"{path}:{number}: 'numbers' is not an object of name to number; "
                          f"expected {what}")
        night["line"], night["raw"] = number, line
        nights.append(night)
    return nights, text


def rounded(value):
    """6 significant figures, ample for bands of 10 %, and a history line a third as long."""
    return float(f"{value:.6g}")


def night_numbers(validations, benchmarks, accuracies):
    """The numbers of tonight's inputs, named kind/group/...: speed/<file>/<benchmark> (ms an
    iteration), error/<backend>/<scene>/<knob>/<setting>, cost/... (wall s per simulated s),
    check/<case>/<quantity>[/<variant>]@<parameter> (|measured - expected| / tolerance; null
    where infinite), passed/<case> (1 or 0), wall/<case> (seconds)."""
    numbers = {}

    def put(name, value):
        key, k = name, 2
        while key in numbers:
            key, k = f"{name} #{k}", k + 1
        numbers[key] = rounded(value) if finite(value) else None

    for s, data in benchmarks:
        stem = os.path.splitext(os.path.basename(s["file"]))[0]
        for _, row in chosen_rows(data):
            unit = TIME_UNIT_MS.get(row.get("time_unit"))
            if not row.get("error_occurred") and unit and finite(row.get("real_time")):
                put(f"speed/{stem}/{row.get('run_name') or row['name']}",
                    row["real_time"] * unit)
    for s, data in accuracies:
        backend = data["meta"].get("backend", "unknown")
        for r in data["rows"]:
            name = f"{backend}/{r['scene']}/{r['knob']}/{r['setting']}"
            if math.isfinite(r["error"]):
                put("error/" + name, r["error"])
            if math.isfinite(cost(r)):
                put("cost/" + name, cost(r))
    for s, data in validations:
        for case in data["cases"]:
            put(f"passed/{case['case']}", 1.0 if case["passed"] else 0.0)
            put(f"wall/{case['case']}", case["wall_seconds"])
        for r in data["results"]:
            if r["verdict"] not in ("pass", "fail"):
                continue
            variant = f"/{r['variant']}" if r.get("variant") else ""
            parameter = r.get("parameter")
            name = f"check/{r['case']}/{r['quantity']}{variant}@" + (
                f"{parameter:g}" if finite(parameter) else "-")
            ratio = error_ratio(r)
            if r["verdict"] == "fail" and finite(ratio) and rounded(ratio) <= 1:
                ratio = 1.000001  # a fail stays a fail once rounded
            put(name, ratio)
    return numbers


def median(values):
    values = sorted(values)
    n = len(values)
    return values[n // 2] if n % 2 else 0.5 * (values[n // 2 - 1] + values[n // 2])


def regressions(numbers, earlier):
    """Each number of tonight's beyond its noise band against the earlier nights (already those
    of tonight's machine), as (name, line of text)."""
    flags = []
    for name, value in numbers.items():
        past = [n["numbers"][name] for n in earlier if name in n["numbers"]]
        if not past:
            continue
        kind = name.split("/", 1)[0]
        recent = [v for v in past[-BASELINE_NIGHTS:] if finite(v)]
        against = f"the median of the last {len(recent)} earlier nights" if len(recent) > 1 \
            else "the earlier night"
        if kind in ("speed", "cost", "wall") and finite(value) and recent:
            base = median(recent)
            if kind == "wall" and min(value, base) < WALL_MIN_SECONDS:
                continue
            if base > 0 and value > base * (1 + SPEED_BAND):
                unit = {"speed": "ms an iteration", "cost": "s a simulated s", "wall": "s"}[kind]
                flags.append((name, f"{name}: {fmt(value)} {unit} against {fmt(base)} "
                                    f"({against}): {fmt(100 * (value / base - 1))} % slower "
                                    f"(band {SPEED_BAND * 100:g} %)"))
        elif kind == "error" and finite(value) and recent:
            base = median(recent)
            if value > base * (1 + ERROR_BAND) and value - base > ERROR_FLOOR:
                rise = f"{fmt(100 * (value / base - 1))} %" if base else "from 0"
                flags.append((name, f"{name}: error {fmt(value)} against {fmt(base)} "
                                    f"({against}): up {rise} (band {ERROR_BAND * 100:g} % and "
                                    f"{ERROR_FLOOR:g})"))
        elif kind == "check":
            was_pass = past[-1] is not None and past[-1] <= 1
            if was_pass and (value is None or value > 1):
                flags.append((name, f"{name}: failed (|measured - expected| / tolerance "
                                    f"{fmt(value) if value is not None else 'infinite'}), passed "
                                    f"the night before ({fmt(past[-1])})"))
        elif kind == "passed" and past[-1] == 1 and value == 0:
            flags.append((name, f"{name}: the case failed; it passed the night before"))
    return flags


def history_group(name):
    """The small multiple a number is drawn in."""
    parts = name.split("/")
    if parts[0] in ("speed", "check"):
        return "/".join(parts[:2])
    if parts[0] in ("error", "cost"):
        return "/".join(parts[:3])  # per backend and scene
    return parts[0]  # wall (every case), passed (not drawn)


def history_chart(nights, flagged):
    """One small multiple per group over the nights given (the last is tonight), of the numbers
    that some earlier night has too: speed, costs, errors and wall times each divided by its
    median over the nights; a case's checks as its worst |measured - expected| / tolerance a
    night. None when no number of tonight's has an earlier value."""
    groups = {}
    for name in nights[-1]["numbers"]:
        earlier = [n["numbers"].get(name) for n in nights[:-1] if name in n["numbers"]]
        if earlier and not name.startswith("passed/"):
            groups.setdefault(history_group(name), []).append(name)
    if not groups:
        return None
    plt = pyplot("the history figure")
    columns = 3
    rows = (len(groups) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(12, 2.7 * rows), squeeze=False)
    x = list(range(len(nights)))
    step = max(1, (len(x) + 7) // 8)  # at most 8 dates under an axis, tonight's always
    labels = [n["date"][5:10] if (len(x) - 1 - k) % step == 0 else ""
              for k, n in enumerate(nights)]
    for ax, (group, names) in zip(axes.flat, groups.items()):
        if group.startswith("check/"):
            worst = []
            for night in nights:
                values = [night["numbers"].get(n, math.nan) for n in names]
                worst.append(math.inf if any(v is None for v in values) else
                             max((v for v in values if finite(v)), default=math.nan))
            floor = 1e-6  # an exact match (0) drawn at the bottom of the log axis
            ax.plot(x, [max(w, floor) if math.isfinite(w) else math.nan for w in worst],
                    marker="o", markersize=3, color="C0")
            for k, w in enumerate(worst):
                if w == math.inf:  # not measured (NaN): a failure, drawn as a red cross
                    ax.plot(k, 1, marker="x", color="red", markersize=8)
            ax.axhline(1, color="red", linewidth=0.8, linestyle="--")
            ax.set_yscale("log")
            plain_log_labels(ax)
            ax.set_ylabel("worst |m - e| / tol", fontsize=7)
        else:
            band = ERROR_BAND if group.startswith("error") else SPEED_BAND
            few = len(names) <= 6
            for n in names:
                series = [night["numbers"].get(n) for night in nights]
                typical = median([v for v in series if finite(v)])
                if typical <= 0:
                    continue  # an error of 0 every night: nothing to draw
                red = n in flagged
                ax.plot(x, [v / typical if finite(v) else math.nan for v in series],
                        marker="o" if few or red else None, markersize=3,
                        linewidth=1.6 if red else 0.7, zorder=3 if red else 2,
                        color="red" if red else (None if few else "0.55"),
                        label=n.split("/", 2)[-1][-40:] if few else None)
            ax.axhline(1 + band, color="red", linewidth=0.8, linestyle="--")
            ax.set_ylabel("÷ its median", fontsize=7)
            ax.grid(True, linewidth=0.3)
            if few:
                ax.legend(fontsize=5, loc="best")
        ax.set_title(f"{group} ({len(names)})", fontsize=8)
        ax.set_xticks(x)
        ax.set_xticklabels(labels, fontsize=6, rotation=45)
        ax.tick_params(axis="y", which="both", labelsize=6)
    for ax in list(axes.flat)[len(groups):]:
        ax.set_visible(False)
    fig.tight_layout()
    return png_of(fig, plt)


def history_blocks(tonight, earlier, path, figures):
    """The history section and the flags for the top of the page: (alert, blocks)."""
    same = [n for n in earlier if n["machine"] == tonight["machine"]]
    flags = regressions(tonight["numbers"], same)
    path = os.path.basename(path)  # not this machine's folders, on a page that may be committed
    bands = (f"Noise bands: speed (benchmark times, the study's wall time per simulated second, "
             f"a case's wall time above {WALL_MIN_SECONDS:g} s) {SPEED_BAND * 100:g} % slower; "
             f"accuracy an error up by {ERROR_BAND * 100:g} % of itself and by "
             f"{ERROR_FLOOR:g}; "
             "validation a check or case that passed and now fails. Compared with the median "
             f"of the last {BASELINE_NIGHTS} earlier nights of the same machine "
             "(reports/README.md, \"History\").")
    blocks = [("h2", "History")]
    if not same:
        blocks.append(("p", f"No earlier night of this machine ({tonight['machine']}) in "
                            f"{path} ({len(earlier)} of other machines): nothing to compare "
                            f"with or draw. Tonight has {len(tonight['numbers']):,} numbers."))
        return [], blocks
    shown = same[-(HISTORY_SHOWN - 1):] + [tonight]
    blocks.append(("p", f"Tonight ({tonight['date']}, {tonight['commit']}, "
                        f"{tonight['machine']}) against {len(same)} earlier nights of the same "
                        f"machine in {path}; the last {len(shown)} drawn. " + bands))
    chart = history_chart(shown, {name for name, _ in flags})
    if chart:
        figures["history.png"] = chart
        blocks.append(("figure", "history.png",
                       "one small multiple per group, of the numbers earlier nights have too: "
                       "each divided by its median over the nights drawn (dashed: the band), "
                       "a case's checks as its worst |measured - expected| / tolerance "
                       "(dashed: the tolerance); regressed numbers red"))
    else:
        blocks.append(("p", "None of tonight's numbers was measured on an earlier night."))
    alert = []
    if flags:
        alert = [f"{len(flags)} numbers regressed beyond their noise band against the earlier "
                 f"nights of {tonight['machine']}:"] + [text for _, text in flags]
    else:
        blocks.append(("p", "Nothing regressed beyond its noise band."))
    return alert, blocks


def md_cell(text):
    return text.replace("|", "\\|").replace("\n", " ")


def to_markdown(title, blocks):
    out = [f"# {title}", ""]
    for block in blocks:
        kind = block[0]
        if kind in ("h2", "h3"):
            out += [("## " if kind == "h2" else "### ") + block[1], ""]
        elif kind == "alert" and block[1]:
            out += [f"**REGRESSED: {block[1][0]}**", ""] + [f"- **{i}**" for i in block[1][1:]]
            out.append("")
        elif kind == "p":
            out += [block[1], ""]
        elif kind == "list" and block[1]:
            out += [f"- {item}" for item in block[1]] + [""]
        elif kind == "table":
            t = block[1]
            if len(block) > 2:
                out += [f"**{block[2]['fold']}**", ""]
            out.append("| " + " | ".join(t.headers) + " |")
            out.append("|" + "---|" * len(t.headers))
            for cells, failed in t.rows:
                cells = [md_cell(c) for c in cells]
                if failed:  # the verdict or result in bold, so that a failure stands out
                    cells = [f"**{c}**" if c.startswith(("FAIL", "skipped")) else c
                             for c in cells]
                out.append("| " + " | ".join(cells) + " |")
            out.append("")
        elif kind == "figure":
            out += [f"![{block[2]}](figures/{block[1]})", "", f"*{block[2]}*", ""]
    return "\n".join(out)


CSS = """html{background:#fff}body{font-family:sans-serif;margin:2em;max-width:90em;color:#222}
.alert{border:2px solid #c00;background:#fde8e8;color:#900;padding:0.5em 1em;margin:1em 0}
.alert p{font-weight:bold;margin:0.3em 0}nav{font-size:0.9em;margin:0 0 1em}
nav a{margin-right:1em}summary{cursor:pointer;margin:0.4em 0}
table{border-collapse:collapse;margin:0.5em 0 1em;font-size:0.9em}
th,td{border:1px solid #bbb;padding:0.2em 0.5em;text-align:left;vertical-align:top}
th{background:#eee}tr.fail td{background:#f6c6c6;color:#800;font-weight:bold}
.figures{display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start}
figure{margin:1em 0}img{max-width:100%}figcaption{font-size:0.9em;color:#555}"""


def anchor(heading):
    return re.sub(r"[^a-z0-9]+", "-", heading.lower()).strip("-")


def to_html(title, blocks, figures, link_figures=False):
    e = html.escape
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>{e(title)}</title><style>{CSS}</style></head><body>", f"<h1>{e(title)}</h1>"]
    sections = [b[1] for b in blocks if b[0] == "h2"]
    out.append("<nav>" + "".join(f'<a href="#{anchor(h)}">{e(h)}</a>' for h in sections)
               + "</nav>")
    in_row = False  # consecutive figures share a row (a flex box that wraps)
    for block in blocks:
        kind = block[0]
        if in_row != (kind == "figure"):
            out.append("</div>" if in_row else '<div class="figures">')
            in_row = kind == "figure"
        if kind == "h2":
            out.append(f'<h2 id="{anchor(block[1])}">{e(block[1])}</h2>')
        elif kind == "h3":
            out.append(f"<h3>{e(block[1])}</h3>")
        elif kind == "alert" and block[1]:
            out.append('<div class="alert"><p>REGRESSED: ' + e(block[1][0]) + "</p><ul>"
                       + "".join(f"<li>{e(i)}</li>" for i in block[1][1:]) + "</ul></div>")
        elif kind == "p":
            out.append(f"<p>{e(block[1])}</p>")
        elif kind == "list" and block[1]:
            out.append("<ul>" + "".join(f"<li>{e(i)}</li>" for i in block[1]) + "</ul>")
        elif kind == "table":
            t = block[1]
            if len(block) > 2:
                out.append(f"<details{' open' if block[2]['open'] else ''}><summary>"
                           f"{e(block[2]['fold'])}</summary>")
            out.append("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in t.headers) + "</tr>")
            for cells, failed in t.rows:
                row_class = ' class="fail"' if failed else ""
                out.append(f"<tr{row_class}>" + "".join(f"<td>{e(c)}</td>" for c in cells)
                           + "</tr>")
            out.append("</table>" + ("</details>" if len(block) > 2 else ""))
        elif kind == "figure":
            png = figures[block[1]]
            source = f"figures/{block[1]}" if link_figures else \
                "data:image/png;base64," + base64.b64encode(png).decode("ascii")
            # A figure under 1,100 pixels (drawn at 120 dpi) is shown at 2/3 of its size, so that
            # two 7-inch figures stand side by side on a wide screen (a row wraps as the window
            # narrows); a wider one (the history's small multiples) at its own, within the page.
            width = int.from_bytes(png[16:20], "big") if png.startswith(PNG_MAGIC) else 900
            width = width * 2 // 3 if width < 1100 else width
            out.append(f'<figure style="width:{width}px;max-width:100%"><img alt="'
                       f'{e(block[2])}" src="{source}"><figcaption>'
                       f"{e(block[2])}</figcaption></figure>")
    if in_row:
        out.append("</div>")
    return "\n".join(out + ["</body></html>", ""])


def write_atomic(path, data):
    """Into a temporary file of the same folder, then renamed over `path`: a reader sees the old
    file or the new one, never half of one."""
    folder = os.path.dirname(path)
    fd, temporary = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--validation", action="append", default=[], metavar="FILE",
                        help="a validation-results.json written by talus validate")
    parser.add_argument("--benchmark", action="append", default=[], metavar="FILE",
                        help="a Google Benchmark JSON file (--benchmark_out_format=json)")
    parser.add_argument("--accuracy", action="append", default=[], metavar="FILE",
                        help="a CSV of talus accuracy (the accuracy-against-time study)")
    parser.add_argument("--history", metavar="FILE",
                        help="JSON lines, one a night: the earlier nights to compare with")
    parser.add_argument("--append-history", metavar="FILE",
                        help="append tonight's numbers to FILE (created if missing; it is the "
                             "history compared with where --history is not given); a night "
                             "of the same date, commit and machine is replaced")
    parser.add_argument("--night-date", metavar="YYYY-MM-DD",
                        help="tonight's date for the history (default: today, UTC)")
    parser.add_argument("--night-commit", metavar="TEXT",
                        help="tonight's commit for the history (default: the first input's)")
    parser.add_argument("--night-machine", metavar="TEXT",
                        help="tonight's machine for the history; only nights of the same "
                             "machine are compared (default: the first input's)")
    parser.add_argument("--provenance", metavar="FILE",
                        help="JSON: input path or file name -> {machine, command, commit, ...}")
    parser.add_argument("--max-check-rows", type=int, default=100, metavar="N",
                        help="a case with more check rows is summarised (default 100)")
    parser.add_argument("--note", action="append", default=[], metavar="TEXT",
                        help="a line for the top of the page (repeatable), e.g. what ran")
    parser.add_argument("--link-figures", action="store_true",
                        help="the page links its figures in figures/ instead of holding them "
                             "(half the size, for a report kept as a folder)")
    parser.add_argument("--title", default="talus report")
    parser.add_argument("--output", required=True, metavar="DIR")
    args = parser.parse_args(argv)
    if not args.validation and not args.benchmark and not args.accuracy:
        parser.error("give at least one --validation, --benchmark or --accuracy file")
    return args


def night_of(args, sources, numbers):
    """Tonight's history line: date, commit and machine given, else from the first input."""
    first = sources[0]
    commit = args.night_commit or re.sub(r" \(the provenance file says .*\)$", "",
                                         first["commit"])
    date = args.night_date or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    return {"date": date, "commit": commit, "machine": args.night_machine or first["machine"],
            "numbers": numbers}


def build(args):
    """Everything read and drawn in memory: (markdown, html, figures by name, the history file's
    new text or None)."""
    provenance = read_provenance(args.provenance)
    validations = [(validation_source(f"V{k}", p, d, provenance_entry(provenance, p)), d)
                   for k, p in enumerate(args.validation, 1) for d in [read_validation(p)]]
    benchmarks = [(benchmark_source(f"B{k}", p, d, provenance_entry(provenance, p)), d)
                  for k, p in enumerate(args.benchmark, 1) for d in [read_benchmark(p)]]
    accuracies = [(accuracy_source(f"A{k}", p, d, provenance_entry(provenance, p)), d)
                  for k, p in enumerate(args.accuracy, 1) for d in [read_accuracy(p)]]
    history_path = args.history or args.append_history
    earlier, appended = [], None
    if history_path:
        earlier, _ = read_history(history_path, missing_ok=not args.history)
    if args.append_history and args.append_history != history_path:
        read_history(args.append_history, missing_ok=True)  # refused before anything is written
    sources = [s for s, _ in validations + benchmarks + accuracies]
    figures = {}
    blocks = provenance_blocks(sources)
    if validations:
        blocks += summary_blocks(validations) + checks_blocks(validations, args.max_check_rows)
        blocks += figure_blocks(validations, figures)
    else:
        blocks += [("h2", "Validation"), ("p", "No validation results given.")]
    if accuracies:
        blocks += accuracy_blocks(accuracies, figures)
    else:
        blocks += [("h2", "Accuracy against time"), ("p", "No accuracy results given.")]
    if benchmarks:
        blocks += speed_blocks(benchmarks, figures) + effect_blocks(benchmarks)
    else:
        blocks += [("h2", "Speed"), ("p", "No benchmark results given.")]
    alert = []
    if history_path or args.append_history:
        tonight = night_of(args, sources, night_numbers(validations, benchmarks, accuracies))
        key = (tonight["date"], tonight["commit"], tonight["machine"])
        # A rerun of tonight's report replaces tonight's line, and is not compared with it.
        earlier = [n for n in earlier if (n["date"], n["commit"], n["machine"]) != key]
        alert, history = history_blocks(tonight, earlier, history_path, figures)
        blocks += history
        if args.append_history:
            kept, _ = read_history(args.append_history, missing_ok=True)
            text = "".join(n["raw"] + "\n" for n in kept
                           if (n["date"], n["commit"], n["machine"]) != key)
            appended = text + json.dumps(tonight, separators=(",", ":")) + "\n"
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    blocks[0:0] = [("alert", alert), ("p", f"Generated {now} by reports/generate.py from the "
                                           "files below."), ("list", args.note)]
    return (to_markdown(args.title, blocks),
            to_html(args.title, blocks, figures, args.link_figures), figures, appended)


def main(argv):
    args = parse_arguments(argv)
    try:
        markdown, page, figures, history = build(args)
        os.makedirs(os.path.join(args.output, "figures"), exist_ok=True)
        for name, png in figures.items():
            write_atomic(os.path.join(args.output, "figures", name), png)
        write_atomic(os.path.join(args.output, "report.md"), markdown.encode("utf-8"))
        write_atomic(os.path.join(args.output, "index.html"), page.encode("utf-8"))
        if history is not None:
            os.makedirs(os.path.dirname(os.path.abspath(args.append_history)), exist_ok=True)
            write_atomic(os.path.abspath(args.append_history), history.encode("utf-8"))
    except Refusal as e:
        print(f"generate.py: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"generate.py: {e.filename or args.output}: cannot write ({e.strerror})",
              file=sys.stderr)
        return 2
    print(f"generate.py: wrote {os.path.join(args.output, 'index.html')} and report.md"
          + (f", appended tonight to {args.append_history}" if history is not None else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
