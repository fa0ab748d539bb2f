#!/usr/bin/python3
"""Tests of the run report (python/aar_stereo/report.py) in Debian's headless Chromium.

    tests/python/test_report.py --build BUILD_DIR --work WORK_DIR [unittest arguments]

Renders nine frames across regions A, B and C (every 75th row of
flightpaths/conops.csv, MSAA x1, depth truth) and the twelve calibration
boards, analyzes them calibrating from the boards (frames 0, 2 and 8 dumped;
frame 0 is too far to measure), builds the report and opens it in headless
Chromium: no console messages, every section in the DOM, a screenshot that
shows the plots and the sensed clouds. Also: a run folder missing a file
gives one line and writes nothing, two builds give the same bytes, and a
run whose dataset is not found still gets a report that says so.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import unittest
from pathlib import Path

import numpy as np
from PIL import Image

REPO = Path(__file__).resolve().parents[2]
SECTIONS = ("record", "regions", "error-vs-range", "icp", "worst", "calibration", "filter")
DUMPED = (0, 2, 8)
ARGS = None


def work(*names):
    return Path(ARGS.work, *names).resolve()


def setUpModule():
    if work().exists():
        shutil.rmtree(work())
    work("datasets").mkdir(parents=True)
    rows = (REPO / "flightpaths" / "conops.csv").read_text().splitlines()
    (work("path.csv")).write_text("\n".join([rows[0]] + rows[1::75]) + "\n")
    render, analyze = Path(ARGS.build, "renderer", "aar-render"), Path(ARGS.build, "analyzer", "aar-analyze")
    dataset = work("datasets", "approach")
    subprocess.run([render, "render", dataset, "--flight-path", work("path.csv"), "--msaa", "1", "--depth",
                    "--no-progress"], check=True)
    subprocess.run([render, "calib", dataset, "--msaa", "1", "--far-boards", "none", "--no-progress"], check=True)
    subprocess.run([analyze, "run", dataset, "--dump-frames", ",".join(map(str, DUMPED)), "--no-progress",
                    "--out", work("results", "approach")], check=True)
    result = report(work("results", "approach"), cwd=work())
    if result.returncode != 0:
        raise RuntimeError(f"the report failed: {result.stderr}")


def report(*args, cwd):
    """python3 -m aar_stereo.report ARGS from the checkout, in `cwd`."""
    return subprocess.run([sys.executable, "-m", "aar_stereo.report", *map(str, args)], cwd=cwd, text=True,
                          capture_output=True, env=dict(os.environ, PYTHONPATH=str(REPO / "python")))


def chromium(page, *args):
    """Headless Chromium (as root: no sandbox; no GPU, no display) on `page` with a fresh profile; the
    completed process, its log (console messages among it) on stderr."""
    binary = shutil.which("chromium")
    if binary is None:
        raise AssertionError("no chromium: install Debian's chromium (scripts/install-deps.sh)")
    profile = work("chromium-profile")
    shutil.rmtree(profile, ignore_errors=True)
    return subprocess.run([binary, "--headless", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}",
                           "--enable-logging=stderr", "--v=0", "--hide-scrollbars", *args, page.as_uri()],
                          text=True, capture_output=True, timeout=120)


def near(pixels, colour, tolerance=24):
    return int((np.abs(pixels.astype(int) - colour).max(axis=-1) <= tolerance).sum())


class BrowserTest(unittest.TestCase):
    page = None

    @classmethod
    def setUpClass(cls):
        cls.page = work("results", "approach", "report.html")

    def test_loads_without_console_messages(self):
        result = chromium(self.page, "--dump-dom")
        self.assertEqual(result.returncode, 0, result.stderr)
        # The report has no script: any console line is an error (a blocked or broken resource, a parse error).
        console = [line for line in result.stderr.splitlines() if ":CONSOLE" in line]
        self.assertEqual(console, [])
        dom = result.stdout
        for section in SECTIONS:
            self.assertIn(f'<section id="{section}">', dom)
        self.assertEqual(dom.count('src="data:image/svg+xml;base64,'), 4)  # range, ICP, calibration, filter
        self.assertEqual(dom.count('src="data:image/png;base64,'), 6 + 1)  # the worst frames and frame 0
        self.assertRegex(dom, r"aar-analyze run \S+/datasets/approach --frames 0: --model shelled "
                              r"--dump-frames \d+(,\d+)* --out \S+/results/approach")
        self.assertIn("12 of 12 board pairs used", dom)
        self.assertIn("only 22 sensed points", dom)  # frame 0, not measured
        self.assertIn("<th>AR VSD</th>", dom)  # the dataset has depth truth: BOP's VSD and full AR
        self.assertIn("<th>AR</th>", dom)

    def test_everything_inline(self):
        text = self.page.read_text()
        references = re.findall(r'(?:src|href)="([^"]*)"', text)
        self.assertGreater(len(references), 10)
        self.assertEqual([r for r in references if not r.startswith(("data:", "#"))], [])
        self.assertNotIn("<script", text)

    def test_screenshot_shows_plots(self):
        shot = work("screenshot.png")
        result = chromium(self.page, f"--screenshot={shot}", "--window-size=1280,7000")
        self.assertEqual(result.returncode, 0, result.stderr)
        pixels = np.asarray(Image.open(shot).convert("RGB"))
        self.assertEqual(pixels.shape, (7000, 1280, 3))
        non_white = (pixels.min(axis=-1) < 235).mean()
        colours = len(np.unique(pixels.reshape(-1, 3), axis=0))
        blue, orange = near(pixels, (31, 119, 180)), near(pixels, (255, 127, 14))
        magenta = near(pixels, (255, 0, 255), 60)
        print(f"screenshot: {non_white:.1%} not white, {colours} colours; pixels of the plots' blue {blue}, "
              f"orange {orange}, of the sensed clouds' magenta {magenta}", file=sys.stderr)
        self.assertGreater(non_white, 0.10)
        self.assertGreater(colours, 5000)  # anti-aliased plots and the rendered aircraft, not flat boxes
        self.assertGreater(blue, 10000)  # matplotlib's first colour: the points, the calibration's bars
        self.assertGreater(orange, 600)  # its second: the filtered error, a stage time
        self.assertGreater(magenta, 100)  # the dumped frames' sensed clouds


class CommandTest(unittest.TestCase):
    def test_same_bytes_twice(self):
        again = work("again.html")
        result = report(work("results", "approach"), "--out", again, cwd=work())
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(again.read_bytes(), work("results", "approach", "report.html").read_bytes())

    def test_missing_file_one_line_nothing_written(self):
        for name in ("run.json", "frames.csv", "summary.json"):
            with self.subTest(name):
                run = work("broken", name.partition(".")[0])
                shutil.rmtree(run, ignore_errors=True)
                shutil.copytree(work("results", "approach"), run)
                (run / name).unlink()
                (run / "report.html").unlink()
                before = sorted(p.name for p in run.iterdir())
                result = report(run, cwd=work())
                self.assertEqual(result.returncode, 1)
                self.assertEqual(result.stdout, "")
                self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
                self.assertRegex(result.stderr, rf"^{re.escape(str(run / name))}: missing ")
                self.assertEqual(sorted(p.name for p in run.iterdir()), before)

    def test_dataset_not_found(self):
        # Neither the current folder nor the run's parent's parent holds a datasets/ folder.
        run = work("moved", "elsewhere", "approach")
        shutil.rmtree(work("moved"), ignore_errors=True)
        shutil.copytree(work("results", "approach"), run)
        result = report(run, "--out", work("moved", "report.html"), cwd=work("moved"))
        self.assertEqual(result.returncode, 0, result.stderr)
        text = work("moved", "report.html").read_text()
        self.assertIn("The run&#x27;s dataset was not found", text)
        self.assertIn("over the dump&#x27;s overlay", text)
        self.assertIn("--dump-frames", text)
        self.assertIn(" DATASET ", text)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", required=True)
    parser.add_argument("--work", required=True)
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0]] + rest, verbosity=2)
