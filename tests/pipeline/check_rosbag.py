#!/usr/bin/env python3
"""Reads a bag of `aar-analyze export --format rosbag` with Debian's
python3-rosbag (a reader this project did not write) and checks it against
the dataset it came from: topics, types and their MD5 sums against the
installed message packages, message counts, stamps, one image's pixels, the
camera info, the truth and the run's estimates.

Usage: check_rosbag.py BAG DATASET FIRST COUNT [RUN]
Prints "rosbag ok: ..." and exits 0, or names the first difference and exits 1.
"""
import csv
import json
import math
import sys
from pathlib import Path

import numpy as np
import rosbag
from geometry_msgs.msg import PoseStamped
from PIL import Image as PilImage
from sensor_msgs.msg import CameraInfo, Image
from tf2_msgs.msg import TFMessage


def fail(text):
    print(f"rosbag check: {text}")
    sys.exit(1)


def expect(condition, text):
    if not condition:
        fail(text)


def quaternion_of(rotation):
    """Unit quaternion (x, y, z, w), w >= 0, of a 3x3 rotation (numerically robust form)."""
    r = np.asarray(rotation, dtype=float)
    w = math.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2.0, r[2, 1] - r[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2.0, r[0, 2] - r[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2.0, r[1, 0] - r[0, 1])
    return np.array([x, y, z, w])


def rotation_of(roll_deg, pitch_deg, yaw_deg):
    """Rz(yaw) Ry(pitch) Rx(roll), docs/frames.md."""
    cr, sr = math.cos(math.radians(roll_deg)), math.sin(math.radians(roll_deg))
    cp, sp = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
    cy, sy = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def same_rotation(q, expected):
    return min(np.abs(q - expected).max(), np.abs(q + expected).max()) < 1e-7


def main():
    bag_path, dataset, first, count = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    run = Path(sys.argv[5]) if len(sys.argv) > 5 else None
    frames = list(range(first, first + count))
    sidecars = {i: json.loads((dataset / "frames" / f"{i:06d}.json").read_text()) for i in frames}
    estimates = {}
    if run:
        with open(run / "frames.csv", newline="") as f:
            estimates = {int(r["frame"]): r for r in csv.DictReader(f) if r["status"] == "ok" and int(r["frame"]) in sidecars}

    bag = rosbag.Bag(str(bag_path))
    info = bag.get_type_and_topic_info()
    installed = {c._type: c._md5sum for c in (Image, CameraInfo, TFMessage, PoseStamped)}
    for name, md5 in info.msg_types.items():
        expect(installed.get(name) == md5, f"{name}: MD5 {md5}, the installed package has {installed.get(name)}")
    want = {"/stereo/left/image_raw": ("sensor_msgs/Image", count), "/stereo/right/image_raw": ("sensor_msgs/Image", count),
            "/stereo/left/camera_info": ("sensor_msgs/CameraInfo", count),
            "/stereo/right/camera_info": ("sensor_msgs/CameraInfo", count), "/tf": ("tf2_msgs/TFMessage", count),
            "/tf_static": ("tf2_msgs/TFMessage", 1), "/receiver/pose_truth": ("geometry_msgs/PoseStamped", count)}
    if run:
        want["/receiver/pose_estimate"] = ("geometry_msgs/PoseStamped", len(estimates))
    got = {t: (v.msg_type, v.message_count) for t, v in info.topics.items()}
    expect(got == want, f"topics {got}, expected {want}")

    seen = {t: [] for t in want}
    for topic, msg, t in bag.read_messages():
        seen[topic].append(msg)
        if topic == "/tf_static":
            continue
        stamp = msg.transforms[0].header.stamp if topic == "/tf" else msg.header.stamp
        seq = msg.transforms[0].header.seq if topic == "/tf" else msg.header.seq
        expect(seq in sidecars, f"{topic}: seq {seq} is not an exported frame")
        time_s = sidecars[seq]["time_s"]
        expect(abs(stamp.to_sec() - time_s) < 1e-9 and abs(t.to_sec() - time_s) < 1e-9,
               f"{topic} frame {seq}: stamp {stamp.to_sec()}, record time {t.to_sec()}, flight path {time_s}")
    # Stamps in the flight path's order, one message per frame and topic.
    for topic in want:
        if topic in ("/tf_static", "/receiver/pose_estimate"):
            continue
        seqs = [m.transforms[0].header.seq if topic == "/tf" else m.header.seq for m in seen[topic]]
        expect(seqs == frames, f"{topic}: frames {seqs}, expected {frames}")

    # One image's pixels: the left image of the first frame, as the PNG holds them.
    image = seen["/stereo/left/image_raw"][0]
    stored = PilImage.open(dataset / "frames" / f"{first:06d}_left.png")
    if stored.mode.startswith("I"):  # a thermal rig's 16-bit grey view
        png = np.asarray(stored).astype(np.uint16)
        expect(image.encoding == "mono16" and image.is_bigendian == 0 and image.step == image.width * 2,
               f"image encoding {image.encoding}, step {image.step}")
        pixels = np.frombuffer(image.data, dtype="<u2").reshape(image.height, image.width)
    else:
        png = np.asarray(stored.convert("RGB"))
        expect(image.encoding == "rgb8" and image.is_bigendian == 0 and image.step == image.width * 3,
               f"image encoding {image.encoding}, step {image.step}")
        pixels = np.frombuffer(image.data, dtype=np.uint8).reshape(image.height, image.width, 3)
    expect(pixels.shape == png.shape and np.array_equal(pixels, png), "the left image's pixels differ from the PNG's")
    expect(image.header.frame_id == "left_camera", f"image frame_id {image.header.frame_id}")

    # Camera info: the ideal calibration's intrinsics and the right camera's Tx = -f b.
    rig = sidecars[first]
    left_info, right_info = seen["/stereo/left/camera_info"][0], seen["/stereo/right/camera_info"][0]
    expect(left_info.width == png.shape[1] and left_info.height == png.shape[0], "camera info size")
    expect(left_info.distortion_model == "plumb_bob" and len(left_info.D) == 5, f"distortion {left_info.D}")
    baseline = -rig["right_from_left"]["translation_m"][0]
    f = right_info.P[0]
    expect(abs(right_info.P[3] + f * baseline) < 1e-6 * f, f"right P Tx {right_info.P[3]}, expected {-f * baseline}")
    expect(left_info.K[0] == left_info.P[0] and left_info.K[8] == 1.0, f"K {left_info.K}, P {left_info.P}")

    # Static transforms: the two cameras a baseline apart.
    static = {t.child_frame_id: t.transform.translation for t in seen["/tf_static"][0].transforms}
    expect(set(static) == {"left_camera", "right_camera"}, f"tf_static children {set(static)}")
    gap = math.dist([static["left_camera"].x, static["left_camera"].y, static["left_camera"].z],
                    [static["right_camera"].x, static["right_camera"].y, static["right_camera"].z])
    expect(abs(gap - baseline) < 1e-9, f"camera centres {gap} m apart, baseline {baseline} m")

    # Truth (tf and pose topic) and estimates against the sidecars and frames.csv.
    for tf, pose in zip(seen["/tf"], seen["/receiver/pose_truth"]):
        truth = sidecars[pose.header.seq]["tanker_from_receiver"]
        children = {t.child_frame_id: t for t in tf.transforms}
        expect(set(children) == ({"receiver", "receiver_estimate"} if pose.header.seq in estimates else {"receiver"}),
               f"/tf frame {pose.header.seq}: children {set(children)}")
        q = quaternion_of(truth["rotation"])
        for name, p, o in (("/tf", children["receiver"].transform.translation, children["receiver"].transform.rotation),
                           ("/receiver/pose_truth", pose.pose.position, pose.pose.orientation)):
            expect(np.allclose([p.x, p.y, p.z], truth["translation_m"], atol=1e-9, rtol=0),
                   f"{name} frame {pose.header.seq}: translation {p}")
            expect(same_rotation(np.array([o.x, o.y, o.z, o.w]), q), f"{name} frame {pose.header.seq}: rotation {o}")
    for pose in seen.get("/receiver/pose_estimate", []):
        r = estimates[pose.header.seq]
        expect(np.allclose([pose.pose.position.x, pose.pose.position.y, pose.pose.position.z],
                           [float(r["est_x_m"]), float(r["est_y_m"]), float(r["est_z_m"])], atol=1e-9, rtol=0),
               f"/receiver/pose_estimate frame {pose.header.seq}: position")
        q = quaternion_of(rotation_of(float(r["est_roll_deg"]), float(r["est_pitch_deg"]), float(r["est_yaw_deg"])))
        o = pose.pose.orientation
        expect(same_rotation(np.array([o.x, o.y, o.z, o.w]), q), f"/receiver/pose_estimate frame {pose.header.seq}")
    print(f"rosbag ok: {sum(len(v) for v in seen.values())} messages on {len(want)} topics, "
          f"{len(seen.get('/receiver/pose_estimate', []))} estimates")


if __name__ == "__main__":
    main()
