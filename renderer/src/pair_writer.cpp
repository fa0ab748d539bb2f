#include "aar/renderer/pair_writer.h"

#include <chrono>
#include <future>
#include <utility>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/progress.h"
#include "aar/renderer/image_encode.h"

namespace aar {
namespace {

// Writes one 8-bit grey PNG and records it in the sidecar as `role`.
void WriteMask(const std::filesystem::path& dataset, const std::string& relative, const std::string& role,
               const GroundTruthImage& truth, const std::vector<uint8_t>& values, FrameSidecar& sidecar) {
  const std::string png = EncodePng(cv::Mat(truth.height, truth.width, CV_8UC1, const_cast<uint8_t*>(values.data())));
  WriteFileAtomic(dataset / relative, png);
  sidecar.files[role] = FileRef{relative, Sha256Hex(png)};
}

// Depth EXR, object ids and the receiver's silhouette of one camera.
void WriteDepthTruth(const std::filesystem::path& dataset, const std::string& prefix, const ViewTruth& view,
                     FrameSidecar& sidecar) {
  const std::string depth_relative = prefix + "_" + view.side + "_depth.exr";
  sidecar.files[view.side + "_depth"] = FileRef{depth_relative, WriteDepthExr(dataset / depth_relative, view.scene)};
  WriteMask(dataset, prefix + "_" + view.side + "_mask.png", view.side + "_mask", view.scene, view.scene.object_id,
            sidecar);
  std::vector<uint8_t> silhouette(view.alone.object_id.size());
  for (size_t i = 0; i < silhouette.size(); ++i) silhouette[i] = view.alone.object_id[i] != 0 ? 255 : 0;
  WriteMask(dataset, prefix + "_" + view.side + "_silhouette.png", view.side + "_silhouette", view.alone, silhouette,
            sidecar);
}

// The PNG of one view: its radiance after each of its effects in turn.
std::string EncodeView(const RenderedPair& pair, size_t view, PngStrategy color_png) {
  const SensorExposure exposure{pair.sidecar.kind == "calib" ? 1u : 0u, pair.sidecar.index, view};
  const LinearImage* radiance = &pair.color[view];
  LinearImage effected;
  for (const ViewEffect* effect : pair.effects[view]) {
    effected = effect->Apply(*radiance, exposure);
    radiance = &effected;
  }
  return EncodePng(pair.radiometric ? ToCentikelvin16(*radiance) : ToSrgb8(*radiance), color_png);
}

}  // namespace

void WriteRenderedPair(const std::filesystem::path& dataset, RenderedPair pair, PngStrategy color_png,
                       PairWriteTimes& times) {
  const std::string prefix = pair.dir + "/" + FrameStem(pair.sidecar.index);
  // The two views are encoded at once (the right one on a second thread), then written in order.
  auto start = std::chrono::steady_clock::now();
  std::future<std::string> right = std::async(std::launch::async, [&] { return EncodeView(pair, 1, color_png); });
  const std::array<std::string, 2> pngs = {EncodeView(pair, 0, color_png), right.get()};
  times.encode_ms += MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  for (size_t view = 0; view < pngs.size(); ++view) {
    const std::string side = view == 0 ? "left" : "right";
    const std::string relative = prefix + "_" + side + ".png";
    WriteFileAtomic(dataset / relative, pngs[view]);
    pair.sidecar.files[side] = FileRef{relative, Sha256Hex(pngs[view])};
  }
  times.write_ms += MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  for (const ViewTruth& view : pair.truth) WriteDepthTruth(dataset, prefix, view, pair.sidecar);
  times.encode_ms += MillisecondsSince(start);
  start = std::chrono::steady_clock::now();
  WriteJsonFile(SidecarPath(dataset, pair.sidecar.kind, pair.sidecar.index), SidecarToJson(pair.sidecar));
  times.write_ms += MillisecondsSince(start);
}

PairWriter::PairWriter(std::filesystem::path dataset, const PairWriterOptions& options)
    : dataset_(std::move(dataset)), options_(options) {
  if (options_.max_queued_pairs < 1) throw Error("pair writer: max_queued_pairs must be at least 1");
  worker_ = std::thread([this] { Work(); });
}

PairWriter::~PairWriter() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

void PairWriter::Push(RenderedPair pair) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return error_ || queue_.size() < options_.max_queued_pairs; });
  wait_ms_ += MillisecondsSince(start);
  if (error_) std::rethrow_exception(error_);
  queue_.push_back(std::move(pair));
  changed_.notify_all();
}

PairWriteTimes PairWriter::Finish() {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return error_ || (queue_.empty() && !writing_); });
  wait_ms_ += MillisecondsSince(start);
  if (error_) std::rethrow_exception(error_);
  return times_;
}

void PairWriter::Work() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    RenderedPair pair = std::move(queue_.front());
    queue_.pop_front();
    writing_ = true;
    changed_.notify_all();  // a place in the queue is free
    lock.unlock();
    PairWriteTimes times;
    std::exception_ptr error;
    try {
      WriteRenderedPair(dataset_, std::move(pair), options_.color_png, times);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    writing_ = false;
    times_.encode_ms += times.encode_ms;
    times_.write_ms += times.write_ms;
    if (error) {
      // The first error stops the worker; the queued pairs stay unwritten.
      error_ = error;
      queue_.clear();
      stop_ = true;
    }
    changed_.notify_all();
  }
}

}  // namespace aar
