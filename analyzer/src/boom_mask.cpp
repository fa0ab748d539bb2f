#include "aar/analyzer/boom_mask.h"

#include <algorithm>
#include <array>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "aar/dataset.h"
#include "aar/error.h"

namespace aar {
namespace {

// Sub-pixel bits of cv::fillConvexPoly's vertices.
constexpr int kShift = 4;
constexpr double kScale = 1 << kShift;
// Projected coordinates are clamped to this many pixels beyond the image
// (a vertex just in front of the near plane projects far out).
constexpr double kClampPx = 1.0e5;

// Sutherland-Hodgman against the plane z = near: the part of the triangle in front of it.
std::vector<Eigen::Vector3d> ClipNear(const std::array<Eigen::Vector3d, 3>& triangle, double near_m) {
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = triangle[i];
    const Eigen::Vector3d& b = triangle[(i + 1) % 3];
    const bool a_in = a.z() >= near_m, b_in = b.z() >= near_m;
    if (a_in) out.push_back(a);
    if (a_in != b_in) out.push_back(a + (b - a) * ((near_m - a.z()) / (b.z() - a.z())));
  }
  return out;
}

}  // namespace

void BoomMaskOptions::Check() const {
  if (margin_px < 0 || margin_px > 64) throw Error("boom mask: margin_px must be in [0, 64]");
  if (!(near_m > 0.0)) throw Error("boom mask: near_m must be positive");
}

BoomMasker::BoomMasker(TriangleMesh boom, TriangleMesh tube, const StereoCalibration& calibration,
                       const Eigen::Isometry3d& tanker_from_rect_left, const BoomMaskOptions& options)
    : boom_(std::move(boom)),
      tube_(std::move(tube)),
      rect_left_from_tanker_(tanker_from_rect_left.inverse()),
      f_(calibration.P1.at<double>(0, 0)),
      fy_(calibration.P1.at<double>(1, 1)),
      cx_(calibration.P1.at<double>(0, 2)),
      cy_(calibration.P1.at<double>(1, 2)),
      right_tx_(calibration.P2.at<double>(0, 3)),
      size_(calibration.image_size),
      options_(options) {
  options_.Check();
}

void BoomMasker::Fill(const TriangleMesh& mesh, const Eigen::Isometry3d& rect_from_object, bool right,
                      cv::Mat1b& out) const {
  // Rectified right pixel: u = (f x + P2(0,3)) / z + cx (P2 = [f 0 cx -f b; 0 f cy 0; 0 0 1 0]).
  const double tx = right ? right_tx_ : 0.0;
  std::vector<cv::Point> polygon;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const std::array<Eigen::Vector3d, 3> corners = {rect_from_object * mesh.vertices[t[0]],
                                                    rect_from_object * mesh.vertices[t[1]],
                                                    rect_from_object * mesh.vertices[t[2]]};
    const std::vector<Eigen::Vector3d> clipped = ClipNear(corners, options_.near_m);
    if (clipped.size() < 3) continue;
    polygon.clear();
    for (const Eigen::Vector3d& p : clipped) {
      const double u = std::clamp((f_ * p.x() + tx) / p.z() + cx_, -kClampPx, kClampPx);
      const double v = std::clamp(fy_ * p.y() / p.z() + cy_, -kClampPx, kClampPx);
      // Pixel (u, v) has its centre at (u, v): fillConvexPoly fills pixel centres inside.
      polygon.emplace_back(static_cast<int>(std::lround(u * kScale)), static_cast<int>(std::lround(v * kScale)));
    }
    cv::fillConvexPoly(out, polygon, cv::Scalar(255), cv::LINE_8, kShift);
  }
}

BoomMasks BoomMasker::Draw(const BoomPose& pose) const {
  BoomMasks masks{cv::Mat1b::zeros(size_), cv::Mat1b::zeros(size_)};
  const Eigen::Isometry3d rect_from_boom = rect_left_from_tanker_ * TankerFromBoom(pose);
  const Eigen::Isometry3d rect_from_tube = rect_left_from_tanker_ * TankerFromBoomTube(pose);
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * options_.margin_px + 1, 2 * options_.margin_px + 1));
  for (const bool right : {false, true}) {
    cv::Mat1b& mask = right ? masks.right : masks.left;
    Fill(boom_, rect_from_boom, right, mask);
    Fill(tube_, rect_from_tube, right, mask);
    if (options_.margin_px > 0) cv::dilate(mask, mask, kernel);
  }
  return masks;
}

size_t BoomMasker::RemoveDisparities(cv::Mat& disparity16, int invalid16, const cv::Point& region_tl,
                                     const BoomMasks& masks) {
  size_t removed = 0;
  const int width = masks.left.cols;
  for (int y = 0; y < disparity16.rows; ++y) {
    const int v = y + region_tl.y;
    if (v < 0 || v >= masks.left.rows) continue;
    int16_t* row = disparity16.ptr<int16_t>(y);
    const uint8_t* left = masks.left.ptr<uint8_t>(v);
    const uint8_t* right = masks.right.ptr<uint8_t>(v);
    for (int x = 0; x < disparity16.cols; ++x) {
      if (row[x] == invalid16) continue;
      const int u = x + region_tl.x;
      if (u < 0 || u >= width) continue;
      const int u_right = static_cast<int>(std::lround(u - row[x] / 16.0));
      if (left[u] != 0 || (u_right >= 0 && u_right < width && right[u_right] != 0)) {
        row[x] = static_cast<int16_t>(invalid16);
        ++removed;
      }
    }
  }
  return removed;
}

double ReceiverOccludedFraction(const cv::Mat& mask, const cv::Mat& silhouette) {
  if (mask.size() != silhouette.size() || mask.type() != CV_8U || silhouette.type() != CV_8U) {
    throw Error("receiver occlusion: the mask and the silhouette must be 8-bit images of one size");
  }
  size_t receiver = 0, hidden = 0;
  for (int v = 0; v < mask.rows; ++v) {
    const uint8_t* ids = mask.ptr<uint8_t>(v);
    const uint8_t* alone = silhouette.ptr<uint8_t>(v);
    for (int u = 0; u < mask.cols; ++u) {
      if (alone[u] == 0) continue;
      ++receiver;
      if (ids[u] == kBoomMaskId) ++hidden;
    }
  }
  return receiver == 0 ? 0.0 : static_cast<double>(hidden) / static_cast<double>(receiver);
}

}  // namespace aar
