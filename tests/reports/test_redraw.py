#!/usr/bin/python3
"""reports/figures/redraw.py on the fixed results directory of data/redraw/ (three cases' checks,
a fourth case listed without its checks.csv, the other three in no directory): the figures it can
draw are written as PNG files, the index names each with the run behind it, and every figure or
directory it cannot use is reported in one line and listed in the index with why. Runs the script
as a command, as a user would. Exit status 77 (skipped) without matplotlib.
"""
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURE = os.path.join(HERE, "data", "redraw")
REDRAW = os.path.join(HERE, "..", "..", "reports", "figures", "redraw.py")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
DRAWN = ("method_fig10_cylinder_wall_impact.png", "blaze_fig13_free_fall_drag.png",
         "blaze_fig15_gravity_packing.png")
NOT_DRAWN = {"method_fig12_mesh_resolution.png": "no results directory holds mesh_resolution",
             "method_fig13_dodecahedron_packing.png": "dodecahedron_packing/checks.csv is missing",
             "method_fig15_rotating_drum.png": "no results directory holds rotating_drum",
             "blaze_fig18_19_hopper_flow.png": "no results directory holds hopper_flow"}


def redraw(*args):
    return subprocess.run([sys.executable, REDRAW, *args], capture_output=True, text=True)


def link(name):
    """A figure's first cell in the index: its name, linked."""
    return f"[`{name}`]({name})"


def section(markdown, title):
    """The lines of the index's section `## title`."""
    lines = markdown.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]
    return [line for line in lines.splitlines() if line.strip()]


def row(lines, first_cell):
    for line in lines:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] == first_cell:
            return cells
    raise AssertionError(f"no row {first_cell!r} in:\n" + "\n".join(lines))


class Scratch(unittest.TestCase):
    def setUp(self):
        self.scratch = tempfile.mkdtemp(prefix="talus-redraw-test-")
        self.out = os.path.join(self.scratch, "figures")
        self.empty = os.path.join(self.scratch, "not-a-run")
        os.makedirs(self.empty)

    def tearDown(self):
        shutil.rmtree(self.scratch)

    def index(self):
        with open(os.path.join(self.out, "README.md"), encoding="utf-8") as f:
            return f.read()

    def copy_fixture(self, name, **changes):
        """The fixture copied to scratch/name with its validation-results.json's keys changed
        (a value of None removes the key)."""
        target = os.path.join(self.scratch, name)
        shutil.copytree(FIXTURE, target)
        path = os.path.join(target, "validation-results.json")
        with open(path) as f:
            data = json.load(f)
        for key, value in changes.items():
            if value is None:
                data.pop(key)
            else:
                data[key] = value
        with open(path, "w") as f:
            json.dump(data, f)
        return target


class FixtureAndBadDirectory(unittest.TestCase):
    """One run of the script, on the fixture and a directory without results."""

    @classmethod
    def setUpClass(cls):
        Scratch.setUp(cls)
        # A figure of an earlier run that this input cannot draw: it must not stay.
        os.makedirs(cls.out)
        with open(os.path.join(cls.out, "method_fig12_mesh_resolution.png"), "wb") as f:
            f.write(PNG_MAGIC)
        cls.result = redraw("--output", cls.out, FIXTURE, cls.empty)
        cls.markdown = Scratch.index(cls)

    @classmethod
    def tearDownClass(cls):
        Scratch.tearDown(cls)

    def test_exit_status_says_something_is_missing(self):
        self.assertEqual(self.result.returncode, 1, self.result.stderr)

    def test_drawable_figures_are_png_files(self):
        for name in DRAWN:
            with open(os.path.join(self.out, name), "rb") as f:
                self.assertEqual(f.read(8), PNG_MAGIC, name)

    def test_missing_figures_are_not_written_and_stale_ones_removed(self):
        for name in NOT_DRAWN:
            self.assertFalse(os.path.exists(os.path.join(self.out, name)), name)
        self.assertEqual(sorted(os.listdir(self.out)), sorted(DRAWN + ("README.md",)))

    def test_one_line_for_each_problem(self):
        lines = self.result.stderr.strip().splitlines()
        bad = [line for line in lines if self.empty in line]
        self.assertEqual(len(bad), 1, lines)
        self.assertIn("no validation-results.json", bad[0])
        for name, why in NOT_DRAWN.items():
            about = [line for line in lines if name in line]
            self.assertEqual(len(about), 1, (name, lines))
            self.assertIn(why, about[0])
        self.assertIn("3 of 7 figures drawn", lines[-1])

    def test_index_names_each_figure_and_its_run(self):
        figures = section(self.markdown, "Figures")
        for name in DRAWN:
            cells = row(figures, link(name))
            self.assertEqual(cells[2].split()[0], "R1", cells)
        runs = section(self.markdown, "Runs")
        cells = row(runs, "R1")
        self.assertEqual(cells[2:6], ["test host, 2 cores", "`fedcba987654`", "cpu", "small"])
        self.assertEqual(cells[6], "`talus validate --output redraw`")

    def test_index_says_what_is_missing_and_why(self):
        missing = section(self.markdown, "Missing")
        for name, why in NOT_DRAWN.items():
            self.assertIn(why, row(missing, f"`{name}`")[2])
        self.assertTrue(any(self.empty in line and "no validation-results.json" in line
                            for line in missing), missing)

    def test_index_lists_the_figures_to_come(self):
        to_come = section(self.markdown, "To come")
        self.assertIn("to come (multi-GPU)", row(to_come, "Method paper Figs. 17-18")[2])
        self.assertTrue(row(to_come, "BLAZE-DEM Fig. 16")[2].startswith("to come"))

    def test_what_agrees_counts_the_checks(self):
        cells = row(section(self.markdown, "Figures"), link(DRAWN[0]))
        # omega+: 2 checked, both within; V_z+: one of two, the failed one 0.05 m/s off at 30.
        self.assertIn("omega+: 2 of 2 checked within their tolerance", cells[3])
        self.assertIn("V_z+: 1 of 2 checked within their tolerance; the worst 0.05 m/s off "
                      "(tolerance 0.02 m/s) at theta 30", cells[3])
        self.assertIn("V_z+ outside the checked angles (reported): up to 0.038 m/s off at 85",
                      cells[4])


class Inputs(Scratch):
    def test_provenance_file_fills_what_the_results_do_not_record(self):
        run = self.copy_fixture("nightly", machine=None, command=None)
        given = os.path.join(self.scratch, "provenance.json")
        with open(given, "w") as f:
            json.dump({"nightly": {"machine": "H100 x1", "command": "scripts/nightly"}}, f)
        result = redraw("--output", self.out, "--provenance", given, run)
        self.assertEqual(result.returncode, 1, result.stderr)
        cells = row(section(self.index(), "Runs"), "R1")
        self.assertEqual([cells[2], cells[6]], ["H100 x1", "`scripts/nightly`"])

    def test_without_provenance_it_says_not_recorded(self):
        run = self.copy_fixture("bare", machine=None, command=None)
        result = redraw("--output", self.out, run)
        self.assertEqual(result.returncode, 1, result.stderr)
        cells = row(section(self.index(), "Runs"), "R1")
        self.assertEqual([cells[2], cells[6]], ["not recorded", "not recorded"])

    def test_a_full_version_is_drawn_before_a_small_one(self):
        full = self.copy_fixture("full", version="full", commit="111111111111")
        small = self.copy_fixture("small", commit="222222222222")
        result = redraw("--output", self.out, full, small)
        self.assertEqual(result.returncode, 1, result.stderr)
        figures = section(self.index(), "Figures")
        cells = row(figures, link("blaze_fig13_free_fall_drag.png"))
        self.assertEqual(cells[2].split()[0], "R1")
        runs = section(self.index(), "Runs")
        self.assertEqual(row(runs, "R2")[7], "none")

    def test_a_checks_file_not_as_talus_writes_it_is_reported_not_fatal(self):
        run = self.copy_fixture("odd")
        with open(os.path.join(run, "free_fall_drag", "checks.csv"), "w") as f:
            f.write("quantity,variant,parameter\nspeed_dt1e-3,production,0.5\n")
        result = redraw("--output", self.out, run)
        self.assertEqual(result.returncode, 1, result.stderr)
        about = [line for line in result.stderr.splitlines()
                 if "blaze_fig13_free_fall_drag.png" in line]
        self.assertEqual(len(about), 1, result.stderr)
        self.assertIn("not as talus validate writes them", about[0])
        self.assertIn("KeyError", about[0])
        self.assertTrue(os.path.exists(os.path.join(self.out, DRAWN[0])))

    def test_bad_provenance_file_is_refused(self):
        given = os.path.join(self.scratch, "provenance.json")
        with open(given, "w") as f:
            f.write("[1, 2")
        result = redraw("--output", self.out, "--provenance", given, FIXTURE)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn("provenance.json", result.stderr)
        self.assertFalse(os.path.exists(self.out))


if __name__ == "__main__":
    if importlib.util.find_spec("matplotlib") is None:  # the script draws with it
        print("SKIPPED: no matplotlib for %s (Debian's python3-matplotlib)" % sys.executable)
        sys.exit(77)
    unittest.main()
