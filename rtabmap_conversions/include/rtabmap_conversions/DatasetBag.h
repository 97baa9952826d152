#pragma once
// Writes a dataset stream (rtabmap::DatasetRecord, from any reader of the core's eval area, or
// the simulator) into a rosbag with the topics and frames of BagLayout.h, ready for
// `rosbag play --clock`:
//  - message stamps and bag times are the dataset's own times (plus timeOffset, see below);
//  - messages are written in time order (a reader yielding an older record is counted in
//    outOfOrder; rosbag still plays the bag in time order);
//  - /tf_static comes first (1 us before the first record, so no sensor message of the same
//    time is played before it), as one message holding every static transform, recorded with
//    the latching flag so `rosbag play` latches it like a static_transform_publisher would. The
//    mountings are gathered from the records up to the first sensor frame and the first second
//    of data (those records are held back meanwhile); if a later record adds or changes one, a
//    new complete /tf_static message is written then;
//  - odometry (kOdometry records, and the odometry pose of sensor frames) goes to /odom and to
//    /tf as odom -> base_link, once per stamp; ground truth to /ground_truth.
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "rtabmap_core/eval/DatasetReader.h"

namespace rosbag {
class Bag;
}

namespace rtabmap_conversions {

struct BagWriterOptions {
  // "none", "bz2" or "lz4" (rosbag chunk compression).
  std::string compression = "none";
  // Seconds added to every dataset stamp. NaN: automatic, 0 unless the dataset's clock starts
  // before 1 s (layouts with synthesised stamps start at 0, which ROS reads as "no stamp" and
  // rosbag refuses): then the smallest whole number of seconds that brings it to >= 1 s.
  double timeOffset = std::numeric_limits<double>::quiet_NaN();
};

struct BagSummary {
  std::map<std::string, uint64_t> messagesPerTopic;
  uint64_t messages = 0;
  uint64_t records = 0;      // dataset records consumed
  uint64_t frames = 0;       // of which sensor frames
  uint64_t outOfOrder = 0;   // records older than one already written
  double startTime = 0.0;    // bag time of the first and last message (s)
  double endTime = 0.0;
  double timeOffset = 0.0;   // what was added to the dataset's stamps
  uint64_t bytes = 0;        // file size, after close()
  double duration() const { return endTime - startTime; }
};

class DatasetBagWriter {
 public:
  // Creates (overwrites) the bag. Throws rtabmap::Error if it cannot be written.
  explicit DatasetBagWriter(const std::string& path, const BagWriterOptions& options = {});
  ~DatasetBagWriter();  // closes the bag if close() was not called
  DatasetBagWriter(const DatasetBagWriter&) = delete;
  DatasetBagWriter& operator=(const DatasetBagWriter&) = delete;

  // Adds one record. Throws rtabmap::FormatError for data the layout cannot hold (several
  // cameras in a frame, an image type without encoding).
  void add(const rtabmap::DatasetRecord& record);
  // Writes what is held back, closes the file and returns the final summary.
  BagSummary close();
  const BagSummary& summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Reads `reader` to its end into a new bag. progress, if set, is called after each record.
BagSummary convertDatasetToBag(rtabmap::DatasetReader& reader, const std::string& path,
                               const BagWriterOptions& options = {},
                               const std::function<void(const BagSummary&)>& progress = {});

}  // namespace rtabmap_conversions
