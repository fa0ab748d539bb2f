#!/usr/bin/python3
"""Tests of the Python reader python/aar_stereo on a dataset and a run made here by the built tools.

    tests/python/test_aar_stereo.py --build BUILD_DIR --work WORK_DIR [unittest arguments]

Renders two frames with depth truth and the twelve calibration boards
(aar-render, MSAA x1), analyzes them (aar-analyze run with the ideal
calibration, one frame dumped), and checks what the package reads against
what independent readers (OpenCV's imread and FileStorage, the csv and json
modules) read from the same files, and that damaged inputs raise DataError
naming the file.
"""

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import unittest
from pathlib import Path

os.environ["OPENCV_IO_ENABLE_OPENEXR"] = "1"  # before cv2 is imported: OpenCV reads OpenEXR only when asked to
import cv2  # noqa: E402
import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
import aar_stereo  # noqa: E402
from aar_stereo import DataError  # noqa: E402

FRAMES = (590, 591)
ARGS = None


def setUpModule():
    work = Path(ARGS.work)
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    render, analyze = Path(ARGS.build, "renderer", "aar-render"), Path(ARGS.build, "analyzer", "aar-analyze")
    dataset, run = work / "dataset", work / "run"
    subprocess.run([render, "render", dataset, "--frames", f"{FRAMES[0]}:{FRAMES[-1] + 1}", "--msaa", "1",
                    "--depth", "--no-progress"], check=True)
    subprocess.run([render, "calib", dataset, "--msaa", "1", "--far-boards", "none", "--no-progress"], check=True)
    subprocess.run([analyze, "run", dataset, "--calibration", dataset / "calibration_ideal.yaml", "--frames",
                    f"{FRAMES[0]}:{FRAMES[-1] + 1}", "--dump-frames", str(FRAMES[1]), "--no-progress", "--out", run],
                   check=True)


def work(name):
    return Path(ARGS.work, name)


def copy(name, to):
    """A fresh copy of the test's dataset or run folder, to damage."""
    target = work(to)
    if target.exists():
        shutil.rmtree(target)
    shutil.copytree(work(name), target)
    return target


def flip_byte(path, offset):
    data = bytearray(path.read_bytes())
    data[offset] ^= 0x01
    path.write_bytes(bytes(data))


def assert_orthonormal(test, pose):
    test.assertEqual(pose.shape, (4, 4))
    np.testing.assert_allclose(pose[:3, :3] @ pose[:3, :3].T, np.eye(3), atol=1e-12)
    test.assertAlmostEqual(np.linalg.det(pose[:3, :3]), 1.0, places=12)
    np.testing.assert_array_equal(pose[3], [0, 0, 0, 1])


class DatasetTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dataset = aar_stereo.open_dataset(work("dataset"))

    def test_frames_in_order(self):
        self.assertEqual(len(self.dataset), len(FRAMES))
        self.assertEqual([f.index for f in self.dataset], list(FRAMES))
        self.assertEqual(self.dataset[-1].index, FRAMES[-1])
        self.assertIs(self.dataset.frame(FRAMES[1]), self.dataset[1])
        with self.assertRaisesRegex(DataError, "lists no frame 0"):
            self.dataset.frame(0)

    def test_images_equal_opencv(self):
        frame = self.dataset.frame(FRAMES[1])
        folder = work("dataset") / "frames"
        for name, image in (("left", frame.left()), ("right", frame.right())):
            self.assertEqual(image.shape, (768, 1024, 3))
            self.assertEqual(image.dtype, np.uint8)
            expected = cv2.imread(str(folder / f"{FRAMES[1]:06d}_{name}.png"), cv2.IMREAD_UNCHANGED)[:, :, ::-1]
            np.testing.assert_array_equal(image, expected)
            self.assertGreater(len(np.unique(image.reshape(-1, 3), axis=0)), 100)  # not a blank image
        depth = frame.depth()
        self.assertEqual((depth.shape, depth.dtype), ((768, 1024), np.float32))
        np.testing.assert_array_equal(depth, cv2.imread(str(folder / f"{FRAMES[1]:06d}_left_depth.exr"),
                                                        cv2.IMREAD_UNCHANGED))
        mask, silhouette = frame.mask(), frame.silhouette()
        self.assertEqual((mask.shape, mask.dtype, silhouette.shape), ((768, 1024), np.uint8, (768, 1024)))
        receiver = mask == 1
        self.assertGreater(receiver.sum(), 1000)
        self.assertTrue((silhouette[receiver] == 255).all())
        # The receiver's depth is about its range (32 m in region C).
        self.assertLess(abs(np.median(depth[receiver]) - frame.range_m), 3.0)
        with self.assertRaisesRegex(DataError, "lists no 'right_depth' file"):
            frame.depth("right")

    def test_poses_equal_sidecar(self):
        for frame in self.dataset:
            sidecar = json.loads(frame.sidecar_path.read_text())
            poses = frame.poses
            for pose in poses.values():
                assert_orthonormal(self, pose)
            np.testing.assert_array_equal(poses["tanker_from_receiver"][:3, :3],
                                          sidecar["tanker_from_receiver"]["rotation"])
            np.testing.assert_array_equal(poses["left_from_receiver"][:3, 3],
                                          sidecar["cam_from_receiver"]["left"]["translation_m"])
            np.testing.assert_array_equal(poses["right_from_left"][:3, 3], sidecar["right_from_left"]["translation_m"])
            # The chains of docs/frames.md.
            np.testing.assert_allclose(np.linalg.inv(poses["tanker_from_left"]) @ poses["tanker_from_receiver"],
                                       poses["left_from_receiver"], atol=1e-9)
            np.testing.assert_allclose(poses["right_from_left"] @ poses["left_from_receiver"],
                                       poses["right_from_receiver"], atol=1e-9)
            # Frame i is sample i of the flight path.
            sample = self.dataset.flight_path[frame.index]
            np.testing.assert_array_equal([sample["x_m"], sample["y_m"], sample["z_m"]],
                                          poses["tanker_from_receiver"][:3, 3])
            self.assertEqual(sample["time_s"], frame.time_s)
        self.assertEqual(len(self.dataset.flight_path), self.dataset.manifest["frames"]["count"])

    def test_calibration_equals_opencv(self):
        calibration = self.dataset.calibration
        storage = cv2.FileStorage(str(work("dataset") / "calibration_ideal.yaml"), cv2.FILE_STORAGE_READ)
        for key in ("M1", "D1", "M2", "D2", "R", "T", "R1", "R2", "P1", "P2", "Q"):
            np.testing.assert_array_equal(calibration[key], storage.getNode(key).mat(), err_msg=key)
        self.assertEqual(calibration["image_size"], self.dataset.image_size)
        self.assertEqual(calibration["Q"][3, 2], 1.0 / 0.5)  # 1 / baseline

    def test_calibration_pairs(self):
        pairs = self.dataset.calib_pairs
        self.assertEqual([p.index for p in pairs], list(range(12)))
        for name in ("tanker_from_board", "left_from_board", "right_from_board"):
            assert_orthonormal(self, pairs[0].poses[name])
        self.assertEqual(pairs[0].left().shape, (768, 1024, 3))

    def test_changed_byte_names_file(self):
        copied = copy("dataset", "tampered")
        changed = copied / "frames" / f"{FRAMES[1]:06d}_right.png"
        flip_byte(changed, 1000)
        with self.assertRaises(DataError) as caught:
            aar_stereo.open_dataset(copied)
        self.assertEqual(caught.exception.path, changed)
        self.assertIn(f"{FRAMES[1]:06d}_right.png: SHA-256 differs from manifest.json's", str(caught.exception))
        # Unverified, the dataset opens, but the changed image is refused when read.
        unverified = aar_stereo.open_dataset(copied, verify=False)
        unverified.frame(FRAMES[1]).left()
        with self.assertRaisesRegex(DataError, "_right.png: SHA-256 differs from the sidecar's"):
            unverified.frame(FRAMES[1]).right()

    def test_missing_file_names_it(self):
        copied = copy("dataset", "missing")
        (copied / "frames" / f"{FRAMES[0]:06d}_left_mask.png").unlink()
        with self.assertRaisesRegex(DataError, r"000590_left_mask.png: missing \(manifest.json lists it\)"):
            aar_stereo.open_dataset(copied)
        (copied / "manifest.json").unlink()
        with self.assertRaisesRegex(DataError, "manifest.json: missing"):
            aar_stereo.open_dataset(copied, verify=False)

    def test_other_settings_sidecar(self):
        copied = copy("dataset", "settings")
        manifest = json.loads((copied / "manifest.json").read_text())
        manifest["image"]["encoding"] = "something else"
        (copied / "manifest.json").write_text(json.dumps(manifest))
        with self.assertRaisesRegex(DataError, "000590.json: rendered with other settings"):
            aar_stereo.open_dataset(copied, verify=False)[0].sidecar


class CalibrationYamlTest(unittest.TestCase):
    def test_bad_yaml_names_line(self):
        path = work("bad.yaml")
        good = (work("dataset") / "calibration_ideal.yaml").read_text()
        path.write_text(good.replace("rows: 3\n   cols: 1", "rows: 2\n   cols: 1"))  # T with 3 values for 2 x 1
        with self.assertRaisesRegex(DataError, r"bad.yaml:\d+: 3 data values for 2 x 1"):
            aar_stereo.read_calibration(path)
        path.write_text(good.replace("[ 1024, 768 ]", "[ 1024, x ]"))
        with self.assertRaisesRegex(DataError, r"bad.yaml:3: 'x' is not a number"):
            aar_stereo.read_calibration(path)


class RunTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.analysis = aar_stereo.open_run(work("run"))

    def test_frames_csv_typed(self):
        with open(work("run") / "frames.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(self.analysis), len(rows))
        self.assertEqual(len(self.analysis), self.analysis.record["frames_analyzed"])
        self.assertEqual(len(self.analysis), len(FRAMES))
        for row, text in zip(self.analysis, rows):
            self.assertEqual(row.keys(), text.keys())
            self.assertEqual(row["frame"], int(text["frame"]))
            self.assertEqual(row["err_x_m"], float(text["err_x_m"]))
            self.assertIsInstance(row["sensed_points"], int)
            self.assertIs(row["icp_converged"], text["icp_converged"] == "1")
            self.assertEqual(row["status"], "ok")
            self.assertEqual(sum(n for n, _ in row["truth_error_by_fraction"]),
                             row["truth_points"] - row["truth_off_receiver"])  # the points on the receiver
        np.testing.assert_array_equal(self.analysis.column("frame"), FRAMES)
        self.assertEqual(self.analysis.column("frame").dtype, np.int64)
        self.assertEqual(self.analysis.column("ms_total").dtype, np.float64)
        self.assertEqual(list(self.analysis.column("region")), [r["region"] for r in rows])
        # The run had depth truth: ten e_VSD per frame, as the CSV's space-separated text says.
        vsd = self.analysis.column("vsd_errors")
        self.assertEqual(vsd.shape, (len(FRAMES), 10))
        np.testing.assert_array_equal(vsd, [[float(v) for v in r["vsd_errors"].split()] for r in rows])

    def test_against_dataset_truth(self):
        dataset = aar_stereo.open_dataset(work("dataset"))
        for row, bop in zip(self.analysis, self.analysis.bop_results):
            truth = dataset.frame(row["frame"]).poses["tanker_from_receiver"]
            np.testing.assert_allclose([row["truth_x_m"], row["truth_y_m"], row["truth_z_m"]], truth[:3, 3],
                                       atol=1e-6)
            self.assertEqual(bop["im_id"], row["frame"])
            np.testing.assert_allclose(bop["R"] @ bop["R"].T, np.eye(3), atol=1e-6)
            # The estimate is within a metre of the truth in the left camera (t in mm).
            left = dataset.frame(row["frame"]).poses["left_from_receiver"]
            self.assertLess(np.linalg.norm(bop["t"] / 1000.0 - left[:3, 3]), 1.0)
        summary = self.analysis.summary
        self.assertEqual(summary["models"][self.analysis.record["model"]]["all"]["ok"], len(FRAMES))
        np.testing.assert_array_equal(self.analysis.calibration["Q"], dataset.calibration["Q"])

    def test_frame_dump(self):
        self.assertEqual(list(self.analysis.dumps), [FRAMES[1]])
        dump = self.analysis.dumps[FRAMES[1]]
        points = dump.points()
        row = self.analysis[1]
        self.assertEqual(len(points["u_px"]), row["sensed_points"])
        on = ~np.isnan(points["true_disparity_px"])
        self.assertEqual(on.sum(), row["truth_points"] - row["truth_off_receiver"])
        self.assertAlmostEqual((points["disparity_px"] - points["true_disparity_px"])[on].sum(),
                               row["truth_error_sum_px"], places=3)
        self.assertEqual(dump.sensed().shape, (row["sensed_points"], 3))
        self.assertEqual(dump.disparity().shape, (768, 1024, 3))
        self.assertEqual(self.analysis.reference_cloud().shape[1], 3)

    def test_missing_frames_csv_names_it(self):
        copied = copy("run", "run-missing")
        (copied / "frames.csv").unlink()
        with self.assertRaises(DataError) as caught:
            aar_stereo.open_run(copied)
        self.assertEqual(caught.exception.path, copied / "frames.csv")
        self.assertIn("frames.csv: missing", str(caught.exception))

    def test_short_frames_csv_names_it(self):
        copied = copy("run", "run-short")
        lines = (copied / "frames.csv").read_text().splitlines(keepends=True)
        (copied / "frames.csv").write_text("".join(lines[:-1]))
        with self.assertRaisesRegex(DataError, r"frames.csv: 1 rows, but run.json says 2 frames were analyzed"):
            aar_stereo.open_run(copied)
        (copied / "frames.csv").write_text("".join(lines).replace(",ok,", ",ok,,,", 1))
        with self.assertRaisesRegex(DataError, r"frames.csv:2: 61 fields, the header has 59"):
            aar_stereo.open_run(copied)


class CompareRunsTest(unittest.TestCase):
    def test_mean_absolute_error(self):
        """experiments/compare_runs.py (which reads runs with the package) against the package's columns."""
        out = subprocess.run([sys.executable, REPO / "experiments" / "compare_runs.py", f"a={work('run')}"],
                             check=True, capture_output=True, text=True).stdout
        cells = next(line for line in out.splitlines() if line.startswith("| C | a |")).split(" | ")
        run = aar_stereo.open_run(work("run"))
        self.assertEqual(cells[2], f"{len(FRAMES)}/{len(FRAMES)}")
        self.assertEqual(cells[3], f"{np.mean(np.abs(run.column('err_x_m'))):.3f}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", required=True, help="build folder with renderer/aar-render, analyzer/aar-analyze")
    parser.add_argument("--work", required=True, help="scratch folder (emptied first)")
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0]] + rest)
