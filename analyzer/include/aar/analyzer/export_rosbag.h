#pragma once
// A ROS 1 bag (format 2.0, http://wiki.ros.org/Bags/Format/2.0), playable
// with `rosbag play` and read by Debian's python3-rosbag: one uncompressed
// chunk per frame, stamped with the flight path's time.
//
//   OUT/dataset.bag
//     /stereo/left/image_raw, /stereo/right/image_raw   sensor_msgs/Image: the
//         dataset's images as stored (rgb8; mono8 for a gray PNG)
//     /stereo/left/camera_info, /stereo/right/camera_info   sensor_msgs/CameraInfo
//         from calibration_ideal.yaml (plumb_bob D, K = M, R = R1/R2, P = P1/P2)
//     /tf_static   tf2_msgs/TFMessage, once, latched: tanker -> left_camera,
//         tanker -> right_camera (the cameras' OpenCV axes, ROS's optical frame)
//     /tf          tf2_msgs/TFMessage per frame: tanker -> receiver (truth) and,
//         with ExportOptions::run, tanker -> receiver_estimate where measured
//     /receiver/pose_truth      geometry_msgs/PoseStamped in the tanker frame
//     /receiver/pose_estimate   geometry_msgs/PoseStamped, the run's measured
//         frames (status ok) among the selected ones
//
// Headers: seq = frame index, stamp = flight-path time, frame_id as above.

#include <string>

#include "aar/analyzer/export_source.h"

namespace aar {

ExportResult ExportRosbag(const ExportOptions& options);

}  // namespace aar
