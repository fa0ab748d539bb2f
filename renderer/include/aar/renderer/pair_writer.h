#pragma once
// Encoding and writing of rendered stereo pairs on a worker thread: pair k is
// converted to sRGB, encoded (PNG, depth EXR), hashed and written atomically
// while pair k + 1 renders (docs/rendering.md, "Encoding beside rendering").
// Pairs are written one at a time in the order they are queued, each pair's
// images before its sidecar, as the single-threaded loop wrote them: the same
// files, and a pair whose sidecar is missing is rendered again on resume.

#include <array>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "aar/dataset.h"
#include "aar/renderer/image_encode.h"
#include "aar/renderer/view_effect.h"

namespace aar {

/// Depth truth of one camera, as rendered (lens resampling done).
struct ViewTruth {
  std::string side;        ///< "left" or "right"
  GroundTruthImage scene;  ///< the whole scene: depth EXR and object-id mask
  GroundTruthImage alone;  ///< the receiver alone: its silhouette
};

/// One rendered stereo pair, everything its files are made of.
struct RenderedPair {
  std::string dir;                   ///< dataset subfolder: frames or calib
  FrameSidecar sidecar;              ///< its files are added as they are written
  std::array<LinearImage, 2> color;  ///< linear colour of the views, left then right
  std::vector<ViewTruth> truth;      ///< depth truth of the cameras asked for (none by default)
  /// Each view's effects (view_effect.h: the lens's resampling, the sensor),
  /// applied in order before its sRGB encoding, never to the truth; none:
  /// the rendered radiance is encoded. The render job's session owns them
  /// and outlives its writer.
  std::array<std::vector<const ViewEffect*>, 2> effects;
  /// A thermal pair: the effects end in brightness temperatures, written as
  /// radiometric 16-bit PNGs (ToCentikelvin16) instead of sRGB.
  bool radiometric = false;
};

/// Time spent per stage [ms], summed over the pairs written.
struct PairWriteTimes {
  double encode_ms =
      0.0;  ///< lens resampling, sensor model, sRGB conversion, PNG and EXR encoding (and the truth files' writes)
  double write_ms = 0.0;  ///< hashing and atomic writes of the colour images and sidecars
};

struct PairWriterOptions {
  /// Rendered pairs that may wait for the worker besides the one it writes;
  /// the renderer waits beyond. Each holds its linear images (19 MB a pair at
  /// 1024 x 768), so this bounds the memory.
  size_t max_queued_pairs = 2;
  /// PNG settings of the colour images (masks keep the default): kFast over
  /// a textured background.
  PngStrategy color_png = PngStrategy::kDefault;
};

/// Applies each view's effects and encodes (the two views' PNGs at once), hashes and writes one pair
/// into `dataset`, the images in order and the sidecar last; the worker's job.
void WriteRenderedPair(const std::filesystem::path& dataset, RenderedPair pair, PngStrategy color_png,
                       PairWriteTimes& times);

/// One worker thread (and, per pair, a second for the right view's PNG) and a
/// bounded queue of rendered pairs.
class PairWriter {
 public:
  explicit PairWriter(std::filesystem::path dataset, const PairWriterOptions& options = {});
  /// Stops the worker after the pair it is writing; pairs still queued are
  /// not written (a later run renders them: they have no sidecar).
  ~PairWriter();
  PairWriter(const PairWriter&) = delete;
  PairWriter& operator=(const PairWriter&) = delete;

  /// Queues a pair, waiting while the queue is full. Throws the worker's
  /// error (it stops at its first) instead of queueing.
  void Push(RenderedPair pair);
  /// Waits until every queued pair is written and returns the worker's stage
  /// times; throws the worker's error.
  PairWriteTimes Finish();
  /// Time Push and Finish spent waiting for the worker [ms].
  double wait_ms() const { return wait_ms_; }

 private:
  void Work();

  std::filesystem::path dataset_;
  PairWriterOptions options_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<RenderedPair> queue_;  // guarded by mutex_, as are the four below
  bool writing_ = false;            // the worker holds a pair it took from the queue
  bool stop_ = false;
  std::exception_ptr error_;
  PairWriteTimes times_;
  double wait_ms_ = 0.0;  // the caller's thread only
  std::thread worker_;    // last: started once the members above exist
};

}  // namespace aar
