#!/usr/bin/python3
"""reports/generate.py on the fixed inputs of data/: the numbers that could come out wrong (the
summary's counts, the failed check, the rates as formatted), the figure and its embedding, the
provenance row, the errors (exit status 2, one line naming the file, nothing written) and the
atomic writes. Runs the generator as a command, as a user would. Exit status 77 (skipped)
without matplotlib.
"""
import base64
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")
GENERATE = os.path.join(HERE, "..", "..", "reports", "generate.py")
VALIDATION = os.path.join(DATA, "validation-results.json")
BENCHMARK = os.path.join(DATA, "bench_scenes.json")
MALFORMED = os.path.join(DATA, "malformed.json")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def generate(*args):
    return subprocess.run([sys.executable, GENERATE, *args], capture_output=True, text=True)


def md_rows(markdown, first_cell):
    """The cells of the Markdown table rows whose first cell is `first_cell`."""
    rows = []
    for line in markdown.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cells[0] == first_cell:
            rows.append(cells)
    return rows


class Scratch(unittest.TestCase):
    def setUp(self):
        self.scratch = tempfile.mkdtemp(prefix="talus-reports-test-")
        self.out = os.path.join(self.scratch, "report")

    def tearDown(self):
        shutil.rmtree(self.scratch)

    def write_json(self, name, data):
        path = os.path.join(self.scratch, name)
        with open(path, "w") as f:
            json.dump(data, f)
        return path

    def read(self, name):
        with open(os.path.join(self.out, name), encoding="utf-8") as f:
            return f.read()


class BothInputs(Scratch):
    def setUp(self):
        super().setUp()
        result = generate("--validation", VALIDATION, "--benchmark", BENCHMARK,
                          "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.markdown, self.html = self.read("report.md"), self.read("index.html")

    def test_summary_counts(self):
        # source, case, result, passed, failed, reported, backend, wall time, commit
        rows = {r[1]: r for r in md_rows(self.markdown, "V1") if len(r) == 9}
        self.assertEqual(rows["free_fall_drag"][2:6], ["pass", "2", "0", "1"])
        self.assertEqual(rows["cylinder_wall_impact"][2:6], ["**FAIL**", "1", "1", "1"])
        self.assertEqual(rows["free_fall_drag"][7], "1.235 s")
        self.assertEqual(rows["cylinder_wall_impact"][8], "abc1234def56")

    def test_failed_check_is_marked(self):
        # 0.123456 against 0.1 +- 0.005: measured to 4 figures, marked failed in both pages.
        failed = [r for r in md_rows(self.markdown, "V1") if "0.1235" in r]
        self.assertEqual(len(failed), 1)
        self.assertEqual(failed[0][2:], ["omega_after (rad/s)", "theta at 20", "0.1235", "0.1",
                                         "0.005", "**FAIL**"])
        self.assertIn("<tr class=\"fail\"><td>V1</td><td>cylinder_wall_impact</td>"
                      "<td>omega_after (rad/s)</td><td>theta at 20</td><td>0.1235</td>", self.html)
        # The passed row of the same quantity is not marked.
        self.assertNotIn("class=\"fail\"><td>V1</td><td>cylinder_wall_impact</td>"
                         "<td>omega_after (rad/s)</td><td>theta at 10</td>", self.html)

    def test_speed_numbers(self):
        rows = {r[1]: r for r in md_rows(self.markdown, "B1")}
        scene = rows["scenes/bed_1e4/cuda/iterations:2000"]
        # time, steps/s, particle-steps/s, particles, bytes a particle, threads (the counter's
        # 16, not the row's own `threads` of 1)
        self.assertEqual(scene[2:8], ["0.7681 ms", "1,235", "12,350,000", "10,192", "—", "16"])
        gpu = rows["gpu_step/dodecahedron_bed/100/0"]
        self.assertEqual(gpu[4:7], ["146,600,000 (polyhedra)", "1,000,000", "1,236"])
        self.assertEqual(rows["host_step/all_effects/threads:2"][4], "143,900")
        self.assertIn("<td>12,350,000</td>", self.html)

    def test_figure_is_a_png_and_embedded(self):
        with open(os.path.join(self.out, "figures", "speed.png"), "rb") as f:
            png = f.read()
        self.assertTrue(png.startswith(PNG_MAGIC))
        self.assertGreater(len(png), 1000)
        self.assertIn("data:image/png;base64," + base64.b64encode(png).decode(), self.html)
        self.assertIn("](figures/speed.png)", self.markdown)

    def test_provenance_rows(self):
        rows = {r[0]: r for r in md_rows(self.markdown, "V1") + md_rows(self.markdown, "B1")
                if r[1] in ("validation", "benchmark")}
        # source, kind, file, machine, commit, command, date, also recorded
        self.assertEqual(rows["V1"][4], "abc1234def56")
        self.assertEqual(rows["V1"][3], "not recorded")
        self.assertEqual(rows["B1"][4], "fedcba987654")
        self.assertEqual(rows["B1"][3], "host testhost, 16 CPUs at 3000 MHz, NVIDIA H100")
        self.assertIn("./bench_scenes", rows["B1"][5])

    def test_case_figure_missing_is_said(self):
        self.assertIn("figure cylinder_wall_impact/figure.png is not beside the file",
                      self.markdown)

    def test_rerun_replaces_files_and_leaves_no_temporaries(self):
        os.utime(os.path.join(self.out, "index.html"), (0, 0))
        result = generate("--benchmark", BENCHMARK, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("No validation results given.", self.read("report.md"))
        self.assertGreater(os.path.getmtime(os.path.join(self.out, "index.html")), 0)
        self.assertEqual(sorted(os.listdir(self.out)), ["figures", "index.html", "report.md"])
        self.assertEqual(os.listdir(os.path.join(self.out, "figures")), ["speed.png"])


class OneKindOfInput(Scratch):
    def test_validation_only(self):
        result = generate("--validation", VALIDATION, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("No benchmark results given.", self.read("index.html"))
        self.assertFalse(os.path.exists(os.path.join(self.out, "figures", "speed.png")))

    def test_provenance_file_fills_in(self):
        provenance = self.write_json("provenance.json", {"validation-results.json": {
            "machine": "H100 x1", "command": "talus validate --small", "commit": "abc1234def56"}})
        result = generate("--validation", VALIDATION, "--provenance", provenance,
                          "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        row = [r for r in md_rows(self.read("report.md"), "V1") if r[1] == "validation"][0]
        self.assertEqual(row[3:6], ["H100 x1", "abc1234def56", "talus validate --small"])

    def test_large_case_is_summarised(self):
        rows = [{"case": "big", "quantity": "kinetic_energy", "variant": "linear",
                 "parameter": k, "measured": k * 1.0, "expected": 0.0, "tolerance": 0.0,
                 "verdict": "reported"} for k in range(150)]
        # The worst checked row is the one furthest from expected in tolerances (3.0 of 0.5).
        for measured in (1.1, 3.0, 1.9):
            rows.append({"case": "big", "quantity": "energy", "parameter": measured,
                         "measured": measured, "expected": 1.0, "tolerance": 10.0,
                         "verdict": "pass"})
        case = {"case": "big", "passed": True, "checks_passed": 3, "checks_failed": 0,
                "reported": 150, "wall_seconds": 1.0}
        path = self.write_json("big.json", {"commit": "c", "backend": "cpu", "version": "small",
                                            "passed": True, "cases": [case], "results": rows})
        result = generate("--validation", path, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        markdown = self.read("report.md")
        shown = [r for r in md_rows(markdown, "V1") if len(r) == 8 and r[1] == "big"]
        self.assertEqual([r[4] for r in shown], ["3"])
        self.assertIn("153 rows summarised as 1", markdown)
        self.assertIn("kinetic_energy linear (150 reported rows)", markdown)

    def test_repetitions_give_the_median(self):
        def row(run_type, aggregate, time):
            return {"name": "bench" + (f"_{aggregate}" if aggregate else ""), "run_name": "bench",
                    "run_type": run_type, "aggregate_name": aggregate, "repetitions": 2,
                    "iterations": 10, "real_time": time, "cpu_time": time, "time_unit": "us"}
        rows = [row("iteration", None, 1.0), row("iteration", None, 3.0),
                row("aggregate", "mean", 2.0), row("aggregate", "median", 2.5),
                row("aggregate", "stddev", 1.4)]
        path = self.write_json("reps.json", {"context": {}, "benchmarks": rows})
        result = generate("--benchmark", path, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        shown = md_rows(self.read("report.md"), "B1")
        shown = [r for r in shown if len(r) == 9]
        self.assertEqual([(r[1], r[2]) for r in shown], [("bench (median of 2)", "2.5 us")])


class BadInputs(Scratch):
    def assert_refused(self, result, name, *words):
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn(name, result.stderr)
        for word in words:
            self.assertIn(word, result.stderr)
        self.assertNotIn("Traceback", result.stderr)

    def test_malformed_file_writes_nothing(self):
        result = generate("--validation", VALIDATION, "--benchmark", MALFORMED,
                          "--output", self.out)
        self.assert_refused(result, "malformed.json", "not JSON")
        self.assertFalse(os.path.exists(self.out))

    def test_malformed_file_leaves_an_earlier_report_alone(self):
        os.makedirs(self.out)
        with open(os.path.join(self.out, "index.html"), "w") as f:
            f.write("earlier")
        result = generate("--benchmark", MALFORMED, "--output", self.out)
        self.assert_refused(result, "malformed.json")
        self.assertEqual(os.listdir(self.out), ["index.html"])
        self.assertEqual(self.read("index.html"), "earlier")

    def test_missing_key(self):
        with open(VALIDATION) as f:
            data = json.load(f)
        del data["results"]
        path = self.write_json("no-results.json", data)
        self.assert_refused(generate("--validation", path, "--output", self.out),
                            "no-results.json", "'results'")
        self.assertFalse(os.path.exists(self.out))

    def test_benchmark_given_as_validation(self):
        self.assert_refused(generate("--validation", BENCHMARK, "--output", self.out),
                            "bench_scenes.json", "'commit'")

    def test_missing_file(self):
        self.assert_refused(generate("--benchmark", os.path.join(DATA, "absent.json"),
                                     "--output", self.out), "absent.json", "No such file")


if __name__ == "__main__":
    if importlib.util.find_spec("matplotlib") is None:  # the generator draws with it
        print("SKIPPED: no matplotlib for %s (Debian's python3-matplotlib)" % sys.executable)
        sys.exit(77)
    unittest.main()
