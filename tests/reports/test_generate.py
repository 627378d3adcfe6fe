#!/usr/bin/python3
"""reports/generate.py on the fixed inputs of data/: the numbers that could come out wrong (the
summary's counts, the failed check, the rates as formatted, the accuracy study's costs, Pareto
front and best and worst settings, the effects' costs), the figures and their embedding, the
provenance rows, the history's flags (a night 20 % slower flagged, 5 % not, a fresh history
drawing and flagging nothing), the errors (exit status 2, one line naming the file and line,
nothing written) and the atomic writes. Runs the generator as a command, as a user would. Exit
status 77 (skipped) without matplotlib.
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
ACCURACY = os.path.join(DATA, "accuracy.csv")
EFFECTS = os.path.join(DATA, "bench_effects.json")
BAD_HISTORY = os.path.join(DATA, "history-bad.jsonl")
# The fixture's bed_1e4 row (bench_scenes.json): 0.76812 ms an iteration.
BED = "speed/bench_scenes/scenes/bed_1e4/cuda/iterations:2000"
BED_MS = 0.76812
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

    def test_case_with_a_failure_is_unfolded(self):
        self.assertIn("<details open><summary>V1 cylinder_wall_impact: 1 passed, 1 failed, "
                      "1 reported</summary>", self.html)
        self.assertIn("<details><summary>V1 free_fall_drag: 2 passed, 0 failed, 1 reported"
                      "</summary>", self.html)
        self.assertIn("**V1 free_fall_drag: 2 passed, 0 failed, 1 reported**", self.markdown)

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

    def test_one_verdict_line_for_files_that_agree(self):
        result = generate("--validation", VALIDATION, "--validation", VALIDATION,
                          "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("- V1, V2: a case FAILS (small versions, backend cpu, commit "
                      "abc1234def56).", self.read("report.md"))

    def test_linked_figures(self):
        result = generate("--benchmark", BENCHMARK, "--link-figures", "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        html = self.read("index.html")
        self.assertIn('src="figures/speed.png"', html)
        self.assertNotIn("data:image/png", html)

    def test_notes_at_the_top(self):
        result = generate("--benchmark", BENCHMARK, "--note", "nightly part tests: failed",
                          "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        markdown = self.read("report.md")
        self.assertLess(markdown.index("- nightly part tests: failed"),
                        markdown.index("## Provenance"))

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


class Accuracy(Scratch):
    def setUp(self):
        super().setUp()
        result = generate("--accuracy", ACCURACY, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.markdown = self.read("report.md")
        # source, knob, setting, scene, error, error of, cost, particles, backend, Pareto
        self.rows = {(r[1], r[2], r[3]): r for r in md_rows(self.markdown, "A1") if len(r) == 10}

    def test_cost_is_wall_time_per_simulated_second(self):
        # 0.2 s of wall time for 0.1 s simulated; 200 s for 2 s.
        self.assertEqual(self.rows[("contact_law", "linear", "impact")][6], "2")
        self.assertEqual(self.rows[("contact_law", "linear", "drum")][6], "100")
        self.assertEqual(self.rows[("skin", "skin 0.1", "packing")][4:10],
                         ["0.001", "bed_height (against finest setting)", "40", "63", "cpu",
                          "front"])

    def test_pareto_front_per_scene(self):
        status = {key: r[9] for key, r in self.rows.items()}
        # volume (0.02 at 4 s) is beaten by float precision (0.02 at 3 s) of another knob.
        self.assertEqual(status[("contact_law", "volume", "impact")], "dominated")
        self.assertEqual(status[("precision", "float", "impact")], "front")
        self.assertEqual(status[("shape_resolution", "sphere", "impact")], "front")
        self.assertEqual(status[("skin", "skin 0.4", "packing")], "dominated")
        # The drum's 0-error run is the front of its own scene, not compared with the impact's.
        self.assertEqual(status[("contact_law", "linear", "drum")], "front")
        # The reference rows (error nan) are listed, not drawn.
        self.assertTrue(status[("time_step", "dt/4", "impact")].startswith("not drawn"))
        self.assertEqual(self.rows[("time_step", "dt/4", "impact")][4], "nan")
        self.assertEqual(len(self.rows), 20)
        # A setting listed but not run (error and wall time nan) is listed, not drawn.
        self.assertTrue(status[("contact_law", "volume_paper", "drum")].startswith("not drawn"))
        self.assertEqual(self.rows[("contact_law", "volume_paper", "drum")][6], "nan")

    def test_best_and_worst_line(self):
        # impact: error x cost is lowest for dt/2 (0.001 x 20) on the front, highest for
        # volume_paper (0.03 x 5) among the dominated; shape_resolution spans 0.01 to 0.3.
        self.assertIn("impact (cpu): best accuracy per time time_step 'dt/2' (error 0.001 at 20 s",
                      self.markdown)
        self.assertIn("worst contact_law 'volume_paper' (error 0.03 at 5 s", self.markdown)
        self.assertIn("packing (cpu): best accuracy per time skin 'skin 0.1'", self.markdown)
        self.assertIn("worst skin 'skin 0.4'", self.markdown)
        # The drum's linear run gives its reference's answer (error 0): the best of those that
        # change it is named too.
        self.assertIn("drum (cpu): best accuracy per time contact_law 'linear' (error 0 at 100 s a "
                      "simulated s, on the Pareto front); of the settings that change the "
                      "answer, skin 'skin 0.2' (error 3e-14 at 80 s); no setting is dominated.",
                      self.markdown)
        self.assertIn("Widest error range: shape_resolution (impact: error from 0.01 to 0.3 "
                      "across its settings, a factor 30)", self.markdown)

    def test_figures_and_provenance(self):
        figures = sorted(os.listdir(os.path.join(self.out, "figures")))
        self.assertEqual(figures, ["accuracy-contact_law.png", "accuracy-pareto.png",
                                   "accuracy-precision.png", "accuracy-shape_resolution.png",
                                   "accuracy-skin.png", "accuracy-time_step.png",
                                   "accuracy-wall_mesh.png"])
        html = self.read("index.html")
        for name in figures:
            with open(os.path.join(self.out, "figures", name), "rb") as f:
                png = f.read()
            self.assertTrue(png.startswith(PNG_MAGIC))
            self.assertIn(base64.b64encode(png).decode(), html)
        # The seven figures side by side in one row that wraps, each at 2/3 of its pixels.
        self.assertEqual(html.count('<div class="figures">'), 1)
        self.assertEqual(html.count('<figure style="width:560px;max-width:100%">'), 6)
        row = [r for r in md_rows(self.markdown, "A1") if r[1] == "accuracy"][0]
        self.assertEqual(row[3:7], ["test host, 2 cores", "0123456789ab",
                                    "talus accuracy --output acc",
                                    "2025-11-21T03:00:00+00:00"])
        self.assertIn("backend cpu; 20 rows", row[7])
        self.assertIn("No validation results given.", self.markdown)
        self.assertIn("Not drawn (log axes): 1 row of error 0.", self.markdown)


class Effects(Scratch):
    def test_cost_of_each_effect_per_backend(self):
        result = generate("--benchmark", EFFECTS, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        markdown = self.read("report.md")
        self.assertIn("| effect | cpu (B1): all, ms a step | without it | its cost, ms | "
                      "its cost, % of all | cuda (B1): all, ms a step |", markdown)
        rows = {r[0]: r for r in md_rows(markdown, "walls") + md_rows(markdown, "friction")
                + md_rows(markdown, "drag")}
        # cpu's all is the median of 9, 10 and 12.5 ms (10; the mean is 10.5).
        self.assertEqual(rows["walls"][1:], ["10", "7", "3", "30 %", "2", "1.5", "0.5", "25 %"])
        self.assertEqual(rows["friction"][1:5], ["10", "9", "1", "10 %"])
        self.assertEqual(rows["drag"][1:], ["10", "10.1", "-0.1", "-1 %", "2", "skipped", "—",
                                            "—"])

    def test_two_machines_are_not_mixed(self):
        # The same file given twice stands for two machines' runs: each keeps its own columns,
        # with its own numbers, rather than one median over both.
        result = generate("--benchmark", EFFECTS, "--benchmark", EFFECTS, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        markdown = self.read("report.md")
        self.assertIn("| effect | cpu (B1): all, ms a step | without it | its cost, ms | "
                      "its cost, % of all | cuda (B1): all, ms a step |", markdown)
        self.assertIn("| cpu (B2): all, ms a step |", markdown)
        walls = md_rows(markdown, "walls")[0]
        self.assertEqual(walls[1:9], walls[9:17])


class History(Scratch):
    """Tonight's numbers from the fixtures against a history written here."""
    MACHINE = "test machine"

    def night(self, date, numbers, machine=MACHINE, commit="0000000"):
        return json.dumps({"date": date, "commit": commit, "machine": machine,
                           "numbers": numbers})

    def history(self, *lines):
        path = os.path.join(self.scratch, "history.jsonl")
        with open(path, "w") as f:
            f.write("".join(line + "\n" for line in lines))
        return path

    def run_night(self, history, *inputs):
        result = generate("--benchmark", BENCHMARK, *inputs, "--append-history", history,
                          "--night-date", "2025-11-21", "--night-commit", "1111111",
                          "--night-machine", self.MACHINE, "--output", self.out)
        self.assertEqual(result.returncode, 0, result.stderr)
        return self.read("report.md"), self.read("index.html")

    def nights(self, history):
        with open(history) as f:
            return [json.loads(line) for line in f]

    def test_twenty_percent_slower_is_flagged(self):
        history = self.history(self.night("2025-11-20", {BED: BED_MS / 1.2}))
        markdown, html = self.run_night(history)
        self.assertIn("**REGRESSED: 1 numbers regressed", markdown)
        self.assertIn(f"- **{BED}: 0.7681 ms an iteration against 0.6401 (the earlier night): "
                      "20 % slower (band 10 %)**", markdown)
        # At the very top: before the first section.
        self.assertLess(html.index('<div class="alert">'), html.index("<h2"))
        self.assertTrue(os.path.exists(os.path.join(self.out, "figures", "history.png")))
        nights = self.nights(history)
        self.assertEqual([n["date"] for n in nights], ["2025-11-20", "2025-11-21"])
        self.assertEqual(nights[1]["numbers"][BED], BED_MS)
        self.assertEqual(nights[1]["machine"], self.MACHINE)

    def test_five_percent_slower_is_not(self):
        history = self.history(self.night("2025-11-20", {BED: BED_MS / 1.05}))
        markdown, html = self.run_night(history)
        self.assertNotIn("REGRESSED", markdown)
        self.assertNotIn('class="alert"', html)
        self.assertIn("Nothing regressed beyond its noise band.", markdown)
        self.assertTrue(os.path.exists(os.path.join(self.out, "figures", "history.png")))

    def test_fresh_history_draws_and_flags_nothing(self):
        history = os.path.join(self.scratch, "new", "history.jsonl")
        markdown, html = self.run_night(history)
        self.assertNotIn("REGRESSED", markdown)
        self.assertIn("No earlier night of this machine (test machine)", markdown)
        self.assertFalse(os.path.exists(os.path.join(self.out, "figures", "history.png")))
        nights = self.nights(history)
        self.assertEqual(len(nights), 1)
        self.assertEqual(nights[0]["numbers"][BED], BED_MS)
        self.assertEqual(sorted(os.listdir(os.path.dirname(history))), ["history.jsonl"])

    def test_one_noisy_night_is_outvoted_by_the_median(self):
        # Of three earlier nights one was 20 % faster: the median (tonight's time) is no flag.
        history = self.history(self.night("2025-11-18", {BED: BED_MS}),
                               self.night("2025-11-19", {BED: BED_MS / 1.2}),
                               self.night("2025-11-20", {BED: BED_MS}))
        markdown, _ = self.run_night(history)
        self.assertNotIn("REGRESSED", markdown)

    def test_other_machines_are_not_compared(self):
        history = self.history(self.night("2025-11-20", {BED: BED_MS / 2}, machine="other"))
        markdown, _ = self.run_night(history)
        self.assertNotIn("REGRESSED", markdown)
        self.assertIn("No earlier night of this machine (test machine)", markdown)
        self.assertIn("(1 of other machines)", markdown)

    def test_rerun_replaces_tonight(self):
        history = self.history(self.night("2025-11-20", {BED: BED_MS / 1.2}))
        self.run_night(history)
        markdown, _ = self.run_night(history)
        self.assertIn("REGRESSED", markdown)  # compared with the 20th, not with itself
        self.assertEqual([n["date"] for n in self.nights(history)],
                         ["2025-11-20", "2025-11-21"])
        self.assertEqual(sorted(os.listdir(self.scratch)), ["history.jsonl", "report"])

    def test_pass_that_became_fail(self):
        # Tonight omega_after at theta 20 fails (0.1235 against 0.1 +- 0.005: 4.69 tolerances)
        # and its case with it; the night before both passed. theta 10 passes on both nights.
        check = "check/cylinder_wall_impact/omega_after/theta@20"
        history = self.history(self.night("2025-11-20", {
            check: 0.5, "check/cylinder_wall_impact/omega_after/theta@10": 0.5,
            "passed/cylinder_wall_impact": 1, "passed/free_fall_drag": 1}))
        markdown, _ = self.run_night(history, "--validation", VALIDATION)
        self.assertIn("**REGRESSED: 2 numbers regressed", markdown)
        self.assertIn(f"- **{check}: failed (|measured - expected| / tolerance 4.691), passed "
                      "the night before (0.5)**", markdown)
        self.assertIn("- **passed/cylinder_wall_impact: the case failed", markdown)

    def test_accuracy_band(self):
        # linear's error 0.08 against 0.06: up 33 %, flagged; skin 0.2's 3e-14 against 2e-14:
        # up 50 % but by 1e-14, under the 1e-12 floor; prism 8's 0.1 against 0.095: 5 %.
        history = self.history(self.night("2025-11-20", {
            "error/cpu/impact/contact_law/linear": 0.06,
            "error/cpu/drum/skin/skin 0.2": 2e-14,
            "error/cpu/impact/shape_resolution/prism 8": 0.095}))
        markdown, _ = self.run_night(history, "--accuracy", ACCURACY)
        self.assertIn("**REGRESSED: 1 numbers regressed", markdown)
        self.assertIn("- **error/cpu/impact/contact_law/linear: error 0.08 against 0.06 (the "
                      "earlier night): up 33.33 %", markdown)


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

    def write_text(self, name, text):
        path = os.path.join(self.scratch, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_accuracy_without_a_column(self):
        with open(ACCURACY) as f:
            text = f.read().replace(",error,", ",err,")
        path = self.write_text("no-error.csv", text)
        self.assert_refused(generate("--accuracy", path, "--output", self.out),
                            "no-error.csv:6:", "no column 'error'")
        self.assertFalse(os.path.exists(self.out))

    def test_accuracy_row_not_a_number(self):
        with open(ACCURACY) as f:
            lines = f.read().splitlines()
        lines[7] = lines[7].replace(",0.4,0.1,", ",fast,0.1,")  # line 8: volume's wall time
        path = self.write_text("not-a-number.csv", "\n".join(lines) + "\n")
        self.assert_refused(generate("--accuracy", path, "--output", self.out),
                            "not-a-number.csv:8:", "'wall_seconds' is 'fast'")

    def test_accuracy_wall_time_nan_only_where_not_run(self):
        path = self.write_text("wall.csv", "knob,setting,value,scene,metric,reference,error,"
                               "wall_seconds,simulated_seconds,steps,particles,precision\n"
                               "precision,float,32,impact,m,r,0.1,nan,1,1,1,float\n")
        self.assert_refused(generate("--accuracy", path, "--output", self.out),
                            "wall.csv:2:", "'wall_seconds' is nan")

    def test_accuracy_unknown_knob(self):
        path = self.write_text("knob.csv", "knob,setting,value,scene,metric,reference,error,"
                               "wall_seconds,simulated_seconds,steps,particles,precision\n"
                               "gravity,g,9.8,impact,m,r,0.1,1,1,1,1,double\n")
        self.assert_refused(generate("--accuracy", path, "--output", self.out),
                            "knob.csv:2:", "knob 'gravity'", "contact_law")

    def test_history_line_not_json(self):
        with open(BAD_HISTORY) as f:
            before = f.read()
        self.assert_refused(generate("--benchmark", BENCHMARK, "--append-history", BAD_HISTORY,
                                     "--output", self.out),
                            "history-bad.jsonl:2:", "not JSON", '"numbers"')
        self.assertFalse(os.path.exists(self.out))
        with open(BAD_HISTORY) as f:
            self.assertEqual(f.read(), before)

    def test_history_line_without_numbers(self):
        path = self.write_text("h.jsonl", '{"date": "2025-11-20", "commit": "a", '
                                          '"machine": "m"}\n')
        self.assert_refused(generate("--benchmark", BENCHMARK, "--history", path,
                                     "--output", self.out), "h.jsonl:1:", "numbers")

    def test_missing_file(self):
        self.assert_refused(generate("--benchmark", os.path.join(DATA, "absent.json"),
                                     "--output", self.out), "absent.json", "No such file")


if __name__ == "__main__":
    if importlib.util.find_spec("matplotlib") is None:  # the generator draws with it
        print("SKIPPED: no matplotlib for %s (Debian's python3-matplotlib)" % sys.executable)
        sys.exit(77)
    unittest.main()
