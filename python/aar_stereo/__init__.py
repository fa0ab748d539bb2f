"""Reading the AAR stereo toolkit's datasets and analysis runs in Python (docs/python.md).

    import aar_stereo
    dataset = aar_stereo.open_dataset("datasets/tiny")      # hashes verified
    frame = dataset[0]
    frame.left(), frame.depth(), frame.poses["left_from_receiver"]
    run = aar_stereo.open_run("results/tiny")
    run.column("err_x_m"), run.summary["models"]

Every problem with the data raises `DataError`, naming the file and the reason.
"""

from .calibration import read_calibration
from .dataset import CalibPair, Dataset, Frame, open_dataset, pose_matrix
from .errors import DataError
from .formats import read_exr, read_ply, read_png
from .run import FrameDump, Run, open_run, read_frames_csv

__all__ = ["CalibPair", "DataError", "Dataset", "Frame", "FrameDump", "Run", "open_dataset", "open_run",
           "pose_matrix", "read_calibration", "read_exr", "read_frames_csv", "read_ply", "read_png"]
