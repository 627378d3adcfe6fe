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
    notes = []
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
        notes.append(f"{source['id']}: {verdict} ({data['version']} versions, backend "
                     f"{data['backend']}, commit {data['commit']}).")
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
    table = Table(["source", "case", "quantity", "variant / parameter", "measured", "expected",
                   "tolerance", "verdict"])
    notes = []
    for source, data in validations:
        for case in data["cases"]:
            rows = [r for r in data["results"] if r["case"] == case["case"]]
            shown = rows
            if len(rows) > max_rows:
                shown, left_out = summarised(rows)
                note = (f"{source['id']} {case['case']}: {len(rows):,} rows summarised as "
                        f"{len(shown)}: every failed row and the worst checked row "
                        "(largest |measured - expected| / tolerance) of each quantity")
                if left_out:
                    note += "; not shown: " + ", ".join(left_out)
                notes.append(note + ".")
            counts = {}
            for r in rows:
                counts[quantity_key(r)] = counts.get(quantity_key(r), 0) + 1
            for r in shown:
                show_parameter = counts[quantity_key(r)] > 1 or r.get("parameter")
                table.add(check_cells(source, r, show_parameter), failed=r["verdict"] == "fail")
    blocks = [("h2", "Checks"), ("p", "Failed rows are marked FAIL (red on the HTML page). "
                                       "Tolerances are absolute bounds on |measured - expected|; "
                                       "reported rows are measured, never failed.")]
    return blocks + [("table", table), ("list", notes)]


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


def bar_chart(bars, rate_name):
    try:  # only where there is something to draw
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise Refusal("matplotlib is needed for the speed figure (Debian's python3-matplotlib)")
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
    out = io.BytesIO()
    fig.savefig(out, format="png", dpi=120)
    plt.close(fig)
    return out.getvalue()


def md_cell(text):
    return text.replace("|", "\\|").replace("\n", " ")


def to_markdown(title, blocks):
    out = [f"# {title}", ""]
    for block in blocks:
        kind = block[0]
        if kind in ("h2", "h3"):
            out += [("## " if kind == "h2" else "### ") + block[1], ""]
        elif kind == "p":
            out += [block[1], ""]
        elif kind == "list" and block[1]:
            out += [f"- {item}" for item in block[1]] + [""]
        elif kind == "table":
            t = block[1]
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


CSS = """body{font-family:sans-serif;margin:2em;max-width:90em;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1em;font-size:0.9em}
th,td{border:1px solid #bbb;padding:0.2em 0.5em;text-align:left;vertical-align:top}
th{background:#eee}tr.fail td{background:#f6c6c6;color:#800;font-weight:bold}
figure{margin:1em 0}img{max-width:100%}figcaption{font-size:0.9em;color:#555}"""


def to_html(title, blocks, figures):
    e = html.escape
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>{e(title)}</title><style>{CSS}</style></head><body>", f"<h1>{e(title)}</h1>"]
    for block in blocks:
        kind = block[0]
        if kind in ("h2", "h3"):
            out.append(f"<{kind}>{e(block[1])}</{kind}>")
        elif kind == "p":
            out.append(f"<p>{e(block[1])}</p>")
        elif kind == "list" and block[1]:
            out.append("<ul>" + "".join(f"<li>{e(i)}</li>" for i in block[1]) + "</ul>")
        elif kind == "table":
            t = block[1]
            out.append("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in t.headers) + "</tr>")
            for cells, failed in t.rows:
                row_class = ' class="fail"' if failed else ""
                out.append(f"<tr{row_class}>" + "".join(f"<td>{e(c)}</td>" for c in cells)
                           + "</tr>")
            out.append("</table>")
        elif kind == "figure":
            data = base64.b64encode(figures[block[1]]).decode("ascii")
            out.append(f'<figure><img alt="{e(block[2])}" src="data:image/png;base64,{data}">'
                       f"<figcaption>{e(block[2])}</figcaption></figure>")
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
    parser.add_argument("--provenance", metavar="FILE",
                        help="JSON: input path or file name -> {machine, command, commit, ...}")
    parser.add_argument("--max-check-rows", type=int, default=100, metavar="N",
                        help="a case with more check rows is summarised (default 100)")
    parser.add_argument("--title", default="talus report")
    parser.add_argument("--output", required=True, metavar="DIR")
    args = parser.parse_args(argv)
    if not args.validation and not args.benchmark:
        parser.error("give at least one --validation or --benchmark file")
    return args


def build(args):
    """Everything read and drawn in memory: (markdown, html, figures by name)."""
    provenance = read_provenance(args.provenance)
    validations = [(validation_source(f"V{k}", p, d, provenance_entry(provenance, p)), d)
                   for k, p in enumerate(args.validation, 1) for d in [read_validation(p)]]
    benchmarks = [(benchmark_source(f"B{k}", p, d, provenance_entry(provenance, p)), d)
                  for k, p in enumerate(args.benchmark, 1) for d in [read_benchmark(p)]]
    figures = {}
    blocks = provenance_blocks([s for s, _ in validations + benchmarks])
    if validations:
        blocks += summary_blocks(validations) + checks_blocks(validations, args.max_check_rows)
        blocks += figure_blocks(validations, figures)
    else:
        blocks += [("h2", "Validation"), ("p", "No validation results given.")]
    if benchmarks:
        blocks += speed_blocks(benchmarks, figures)
    else:
        blocks += [("h2", "Speed"), ("p", "No benchmark results given.")]
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    blocks.insert(0, ("p", f"Generated {now} by reports/generate.py from the files below."))
    return to_markdown(args.title, blocks), to_html(args.title, blocks, figures), figures


def main(argv):
    args = parse_arguments(argv)
    try:
        markdown, page, figures = build(args)
        os.makedirs(os.path.join(args.output, "figures"), exist_ok=True)
        for name, png in figures.items():
            write_atomic(os.path.join(args.output, "figures", name), png)
        write_atomic(os.path.join(args.output, "report.md"), markdown.encode("utf-8"))
        write_atomic(os.path.join(args.output, "index.html"), page.encode("utf-8"))
    except Refusal as e:
        print(f"generate.py: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"generate.py: {e.filename or args.output}: cannot write ({e.strerror})",
              file=sys.stderr)
        return 2
    print(f"generate.py: wrote {os.path.join(args.output, 'index.html')} and report.md")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
