#include "aar/analyzer/export_rosbag.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <opencv2/imgproc.hpp>
#include <set>
#include <vector>

#include "aar/analyzer/dataset_image.h"
#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

constexpr const char* kBagName = "dataset.bag";
constexpr const char* kMagic = "#ROSBAG V2.0\n";
constexpr size_t kBagHeaderRecordSize = 4096;  // the bag header record is padded to this (format 2.0)

// Record op codes (Bags/Format/2.0).
constexpr uint8_t kOpMessageData = 0x02;
constexpr uint8_t kOpBagHeader = 0x03;
constexpr uint8_t kOpIndexData = 0x04;
constexpr uint8_t kOpChunk = 0x05;
constexpr uint8_t kOpChunkInfo = 0x06;
constexpr uint8_t kOpConnection = 0x07;

// The message definitions as `gendeps --cat` concatenates them (comments
// left out; the MD5 sums, ROS's hash of the definitions, do not include them).
const std::string kSeparator = "\n" + std::string(80, '=') + "\nMSG: ";
const std::string kHeaderDefinition = "std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id";
const std::string kQuaternionDefinition = "geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w";

struct MessageType {
  const char* name;
  const char* md5sum;
  std::string definition;
};

MessageType ImageType() {
  return {"sensor_msgs/Image", "060021388200f6f0f447d0fcd9c64743",
          "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n"
          "uint8[] data" +
              kSeparator + kHeaderDefinition + "\n"};
}

MessageType CameraInfoType() {
  return {"sensor_msgs/CameraInfo", "c9a58c1b0b154e0e6da7578cb991d214",
          "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] D\nfloat64[9] K\n"
          "float64[9] R\nfloat64[12] P\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi" +
              kSeparator + kHeaderDefinition + kSeparator +
              "sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\n"
              "bool do_rectify\n"};
}

MessageType TfMessageType() {
  return {"tf2_msgs/TFMessage", "94810edda583a504dfda3829e70d7eec",
          "geometry_msgs/TransformStamped[] transforms" + kSeparator +
              "geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
              "geometry_msgs/Transform transform" +
              kSeparator + kHeaderDefinition + kSeparator +
              "geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation" +
              kSeparator + "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z" + kSeparator +
              kQuaternionDefinition + "\n"};
}

MessageType PoseStampedType() {
  return {"geometry_msgs/PoseStamped", "d3812c3cbc69362b77dc0b19b345f8f5",
          "std_msgs/Header header\ngeometry_msgs/Pose pose" + kSeparator + kHeaderDefinition + kSeparator +
              "geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation" + kSeparator +
              "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z" + kSeparator + kQuaternionDefinition + "\n"};
}

// ROS time: seconds and nanoseconds, both uint32.
struct RosTime {
  uint32_t sec = 0;
  uint32_t nsec = 0;
  bool operator<(const RosTime& o) const { return sec != o.sec ? sec < o.sec : nsec < o.nsec; }
};

RosTime ToRosTime(double time_s, const std::string& where) {
  if (!(time_s >= 0.0) || !(time_s < 4294967295.0)) {
    throw Error(where + ": time " + std::to_string(time_s) + " s is not a ROS 1 time (0 to 2^32 s)");
  }
  double whole = std::floor(time_s);
  double nsec = std::round((time_s - whole) * 1e9);
  if (nsec >= 1e9) {
    whole += 1.0;
    nsec = 0.0;
  }
  return {static_cast<uint32_t>(whole), static_cast<uint32_t>(nsec)};
}

// ROS 1 serialization: little-endian, strings and variable arrays prefixed
// by a uint32 length, fixed arrays not.
class Serializer {
 public:
  void U8(uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) U8(static_cast<uint8_t>(v >> (8 * i)));
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) U8(static_cast<uint8_t>(v >> (8 * i)));
  }
  void F64(double v) {
    uint64_t bits = 0;
    static_assert(sizeof(bits) == sizeof(v));
    std::memcpy(&bits, &v, sizeof(v));
    U64(bits);
  }
  void Time(const RosTime& t) {
    U32(t.sec);
    U32(t.nsec);
  }
  void String(const std::string& s) {
    U32(static_cast<uint32_t>(s.size()));
    bytes_ += s;
  }
  void Raw(const std::string& s) { bytes_ += s; }
  void Raw(const char* data, size_t size) { bytes_.append(data, size); }
  // A header field "name=value" with its uint32 length (record headers and connection headers).
  void Field(const std::string& name, const std::string& value) {
    U32(static_cast<uint32_t>(name.size() + 1 + value.size()));
    bytes_ += name + "=" + value;
  }
  void Header(uint32_t seq, const RosTime& stamp, const std::string& frame_id) {
    U32(seq);
    Time(stamp);
    String(frame_id);
  }
  void Transform(const Eigen::Isometry3d& a_from_b) {
    for (int i = 0; i < 3; ++i) F64(a_from_b.translation()[i]);
    const Eigen::Quaterniond q = UnitQuaternion(a_from_b.linear());
    for (double v : {q.x(), q.y(), q.z(), q.w()}) F64(v);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

// A record's header: its fields, the op code first.
class RecordHeader {
 public:
  explicit RecordHeader(uint8_t op) { Field("op", std::string(1, static_cast<char>(op))); }
  RecordHeader& Field(const std::string& name, const std::string& value) {
    fields_.Field(name, value);
    return *this;
  }
  RecordHeader& U32(const std::string& name, uint32_t v) {
    Serializer s;
    s.U32(v);
    return Field(name, s.bytes());
  }
  RecordHeader& U64(const std::string& name, uint64_t v) {
    Serializer s;
    s.U64(v);
    return Field(name, s.bytes());
  }
  RecordHeader& Time(const std::string& name, const RosTime& t) {
    Serializer s;
    s.Time(t);
    return Field(name, s.bytes());
  }
  // header_len, header, data_len, data
  std::string Record(const std::string& data) const {
    Serializer r;
    r.U32(static_cast<uint32_t>(fields_.bytes().size()));
    r.Raw(fields_.bytes());
    r.U32(static_cast<uint32_t>(data.size()));
    r.Raw(data);
    return r.bytes();
  }

 private:
  Serializer fields_;
};

struct Connection {
  uint32_t id = 0;
  std::string topic;
  MessageType type;
  bool latching = false;

  std::string Record() const {
    // The connection header (the data) is a field list of its own, without an op.
    Serializer data;
    data.Field("topic", topic);
    data.Field("type", type.name);
    data.Field("md5sum", type.md5sum);
    data.Field("message_definition", type.definition);
    data.Field("callerid", "/aar_analyze_export");
    if (latching) data.Field("latching", "1");
    return RecordHeader(kOpConnection).U32("conn", id).Field("topic", topic).Record(data.bytes());
  }
};

// The messages of one frame: one chunk, its connection records (first use
// only) and its index records.
class ChunkBuilder {
 public:
  void Add(const Connection& connection, const RosTime& time, const std::string& message) {
    if (written_connections_.insert(connection.id).second) data_ += connection.Record();
    index_[connection.id].push_back({time, static_cast<uint32_t>(data_.size())});
    data_ += RecordHeader(kOpMessageData).U32("conn", connection.id).Time("time", time).Record(message);
    if (!has_time_ || time < start_) start_ = time;
    if (!has_time_ || end_ < time) end_ = time;
    has_time_ = true;
  }
  // Writes the chunk and its index records at `out`'s position; returns the chunk info record.
  std::string Write(std::ofstream& out) {
    const uint64_t chunk_pos = static_cast<uint64_t>(out.tellp());
    const std::string chunk = RecordHeader(kOpChunk)
                                  .Field("compression", "none")
                                  .U32("size", static_cast<uint32_t>(data_.size()))
                                  .Record(data_);
    out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    Serializer counts;
    for (const auto& [id, entries] : index_) {
      Serializer index;
      for (const auto& [time, offset] : entries) {
        index.Time(time);
        index.U32(offset);
      }
      const std::string record = RecordHeader(kOpIndexData)
                                     .U32("ver", 1)
                                     .U32("conn", id)
                                     .U32("count", static_cast<uint32_t>(entries.size()))
                                     .Record(index.bytes());
      out.write(record.data(), static_cast<std::streamsize>(record.size()));
      counts.U32(id);
      counts.U32(static_cast<uint32_t>(entries.size()));
    }
    const std::string info = RecordHeader(kOpChunkInfo)
                                 .U32("ver", 1)
                                 .U64("chunk_pos", chunk_pos)
                                 .Time("start_time", start_)
                                 .Time("end_time", end_)
                                 .U32("count", static_cast<uint32_t>(index_.size()))
                                 .Record(counts.bytes());
    data_.clear();
    index_.clear();
    has_time_ = false;
    return info;
  }

 private:
  std::string data_;
  std::map<uint32_t, std::vector<std::pair<RosTime, uint32_t>>> index_;
  std::set<uint32_t> written_connections_;
  RosTime start_, end_;
  bool has_time_ = false;
};

std::string BagHeaderRecord(uint64_t index_pos, uint32_t connections, uint32_t chunks) {
  const RecordHeader header =
      RecordHeader(kOpBagHeader).U64("index_pos", index_pos).U32("conn_count", connections).U32("chunk_count", chunks);
  const size_t empty = header.Record("").size();
  return header.Record(std::string(kBagHeaderRecordSize - empty, ' '));
}

std::string ImageMessage(const cv::Mat& stored, uint32_t seq, const RosTime& stamp, const std::string& frame_id,
                         const std::string& what) {
  cv::Mat image;
  std::string encoding;
  if (stored.type() == CV_8UC3) {
    cv::cvtColor(stored, image, cv::COLOR_BGR2RGB);  // OpenCV decodes to BGR; the PNG holds RGB
    encoding = "rgb8";
  } else if (stored.type() == CV_8UC1) {
    image = stored;
    encoding = "mono8";
  } else if (stored.type() == CV_16UC1) {  // a thermal rig's radiometric view (0.01 K per count)
    image = stored;
    encoding = "mono16";
  } else {
    throw Error(what + ": not an 8-bit gray or RGB image, nor a 16-bit gray one");
  }
  static_assert(std::endian::native == std::endian::little, "mono16 rows are written as the machine holds them");
  const size_t step = image.cols * image.elemSize();
  Serializer m;
  m.Header(seq, stamp, frame_id);
  m.U32(static_cast<uint32_t>(image.rows));
  m.U32(static_cast<uint32_t>(image.cols));
  m.String(encoding);
  m.U8(0);  // is_bigendian
  m.U32(static_cast<uint32_t>(step));
  m.U32(static_cast<uint32_t>(step * image.rows));
  for (int y = 0; y < image.rows; ++y) m.Raw(image.ptr<char>(y), step);
  return m.bytes();
}

std::string CameraInfoMessage(const StereoCalibration& c, bool left, uint32_t seq, const RosTime& stamp,
                              const std::string& frame_id) {
  Serializer m;
  m.Header(seq, stamp, frame_id);
  m.U32(static_cast<uint32_t>(c.image_size.height));
  m.U32(static_cast<uint32_t>(c.image_size.width));
  m.String("plumb_bob");
  const auto values = [](const cv::Mat& mat) {
    cv::Mat m64;
    mat.convertTo(m64, CV_64F);
    return std::vector<double>(m64.begin<double>(), m64.end<double>());
  };
  const std::vector<double> d = values(left ? c.D1 : c.D2);
  m.U32(static_cast<uint32_t>(d.size()));
  for (double v : d) m.F64(v);
  for (const cv::Mat* mat : {left ? &c.M1 : &c.M2, left ? &c.R1 : &c.R2, left ? &c.P1 : &c.P2}) {
    for (double v : values(*mat)) m.F64(v);
  }
  m.U32(0);                              // binning_x
  m.U32(0);                              // binning_y
  for (int i = 0; i < 4; ++i) m.U32(0);  // roi: the whole image
  m.U8(0);                               // roi.do_rectify
  return m.bytes();
}

struct Stamped {
  std::string child;
  Eigen::Isometry3d parent_from_child;
};

std::string TfMessage(uint32_t seq, const RosTime& stamp, const std::vector<Stamped>& transforms) {
  Serializer m;
  m.U32(static_cast<uint32_t>(transforms.size()));
  for (const Stamped& t : transforms) {
    m.Header(seq, stamp, "tanker");
    m.String(t.child);
    m.Transform(t.parent_from_child);
  }
  return m.bytes();
}

std::string PoseStampedMessage(uint32_t seq, const RosTime& stamp, const Eigen::Isometry3d& tanker_from_receiver) {
  Serializer m;
  m.Header(seq, stamp, "tanker");
  m.Transform(tanker_from_receiver);  // Pose: Point, Quaternion: the same fields as a Transform
  return m.bytes();
}

// The run's measured frames (status ok) by frame index, pointing into `run`.
std::map<size_t, const FrameResult*> MeasuredFramesByIndex(const std::vector<FrameResult>& run) {
  std::map<size_t, const FrameResult*> estimates;
  for (const FrameResult& r : run) {
    if (r.ok()) estimates[r.frame] = &r;
  }
  return estimates;
}

// The bag's connections, each at the index of its id; /receiver/pose_estimate
// (id 7) only with a run.
std::vector<Connection> BagConnections(bool with_run) {
  std::vector<Connection> connections = {
      {0, "/tf_static", TfMessageType(), true},           {1, "/stereo/left/image_raw", ImageType()},
      {2, "/stereo/left/camera_info", CameraInfoType()},  {3, "/stereo/right/image_raw", ImageType()},
      {4, "/stereo/right/camera_info", CameraInfoType()}, {5, "/tf", TfMessageType()},
      {6, "/receiver/pose_truth", PoseStampedType()},
  };
  if (with_run) connections.push_back({7, "/receiver/pose_estimate", PoseStampedType()});
  return connections;
}

// Adds the messages of frame `k` to `chunk`: /tf_static (first frame only),
// both cameras' images and camera infos, /tf, the true pose and, where the
// run measured the frame, the estimated pose.
void AddFrameMessages(ChunkBuilder& chunk, const std::vector<Connection>& connections, const ExportSource& source,
                      size_t k, const StereoCalibration& calibration, const FrameResult* estimate) {
  const FrameSidecar& frame = source.frames[k];
  const std::string sidecar = SidecarPath(source.dataset.folder(), "frame", frame.index).string();
  const RosTime stamp = ToRosTime(frame.time_s, sidecar);
  const uint32_t seq = static_cast<uint32_t>(frame.index);
  if (k == 0) {
    chunk.Add(connections[0], stamp,
              TfMessage(seq, stamp,
                        {{"left_camera", frame.rig.left.tanker_from_camera},
                         {"right_camera", frame.rig.right.tanker_from_camera}}));
  }
  for (const bool left : {true, false}) {
    const char* camera = left ? "left" : "right";
    const std::string frame_id = std::string(camera) + "_camera";
    const cv::Mat image = ReadListedImage(source.dataset, RequireFile(source, frame, camera, "aar-render render"),
                                          cv::IMREAD_UNCHANGED, std::string(camera) + " image");
    chunk.Add(connections[left ? 1 : 3], stamp, ImageMessage(image, seq, stamp, frame_id, sidecar));
    chunk.Add(connections[left ? 2 : 4], stamp, CameraInfoMessage(calibration, left, seq, stamp, frame_id));
  }
  const Eigen::Isometry3d truth = IsometryFromPose(frame.tanker_from_target);
  std::vector<Stamped> tf = {{"receiver", truth}};
  if (estimate) tf.push_back({"receiver_estimate", IsometryFromPose(estimate->estimate)});
  chunk.Add(connections[5], stamp, TfMessage(seq, stamp, tf));
  chunk.Add(connections[6], stamp, PoseStampedMessage(seq, stamp, truth));
  if (estimate) chunk.Add(connections[7], stamp, PoseStampedMessage(seq, stamp, tf.back().parent_from_child));
}

// Writes the index (the connection records, then the chunk info records) at
// `out`'s position and rewrites the bag header record to point at it.
void WriteBagIndex(std::ofstream& out, const std::vector<Connection>& connections,
                   const std::vector<std::string>& chunk_infos) {
  const uint64_t index_pos = static_cast<uint64_t>(out.tellp());
  for (const Connection& c : connections) {
    const std::string record = c.Record();
    out.write(record.data(), static_cast<std::streamsize>(record.size()));
  }
  for (const std::string& info : chunk_infos) out.write(info.data(), static_cast<std::streamsize>(info.size()));
  out.seekp(static_cast<std::streamoff>(std::string(kMagic).size()));
  const std::string header =
      BagHeaderRecord(index_pos, static_cast<uint32_t>(connections.size()), static_cast<uint32_t>(chunk_infos.size()));
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
}

}  // namespace

ExportResult ExportRosbag(const ExportOptions& options) {
  const ExportSource source = ReadExportSource(options);
  const StereoCalibration calibration = ReadIdealCalibration(source);
  const std::vector<FrameResult> run = ReadRunEstimates(options, source);
  const std::map<size_t, const FrameResult*> estimates = MeasuredFramesByIndex(run);
  const std::vector<Connection> connections = BagConnections(options.run.has_value());

  const std::filesystem::path path = options.out / kBagName;
  EnsureWritableDirectory(options.out);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(path.string() + ": cannot create");
  out.write(kMagic, static_cast<std::streamsize>(std::string(kMagic).size()));
  const std::string placeholder = BagHeaderRecord(0, 0, 0);
  out.write(placeholder.data(), static_cast<std::streamsize>(placeholder.size()));

  std::vector<std::string> chunk_infos;
  ChunkBuilder chunk;
  size_t estimates_written = 0;
  for (size_t k = 0; k < source.frames.size(); ++k) {
    const auto estimate = estimates.find(source.frames[k].index);
    const FrameResult* measured = estimate != estimates.end() ? estimate->second : nullptr;
    AddFrameMessages(chunk, connections, source, k, calibration, measured);
    if (measured) ++estimates_written;
    chunk_infos.push_back(chunk.Write(out));
  }
  WriteBagIndex(out, connections, chunk_infos);
  out.close();
  if (!out) throw Error(path.string() + ": write failed");

  ExportResult result;
  result.frames = source.frames.size();
  result.files.push_back(kBagName);
  if (options.run && estimates_written < source.frames.size()) {
    result.notes.push_back("/receiver/pose_estimate: " + std::to_string(source.frames.size() - estimates_written) +
                           " selected frames have no estimate in the run (not analyzed or not measured)");
  }
  return result;
}

}  // namespace aar
