#pragma once
// Internal helpers of the eval area: text input (plain or bzip2, line by line, with the line
// number for error messages), number parsing with file:line errors, folder listings in
// natural order, image loading, and the start/max window shared by the dataset readers.
#include <opencv2/core/mat.hpp>

#include <cstdio>
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/Transform.h"

namespace rtabmap::eval_detail {

// "path:line: message" as a FormatError.
[[noreturn]] void throwAt(const std::string& path, long line, const std::string& message);

// Lines of a text file, plain or bzip2-compressed (told apart by the "BZh" magic, whatever
// the extension), decompressed as a stream. Concatenated bzip2 streams (pbzip2) are read on.
// Throws FormatError on a missing file or corrupt compressed data.
class TextLineReader {
 public:
  explicit TextLineReader(const std::string& path);
  ~TextLineReader();
  TextLineReader(const TextLineReader&) = delete;
  TextLineReader& operator=(const TextLineReader&) = delete;

  // Next line without its end ("\n" or "\r\n"); false at the end of the file.
  bool next(std::string& line);
  long lineNumber() const { return lineNumber_; }
  const std::string& path() const { return path_; }
  bool compressed() const { return bz_ != nullptr; }

 private:
  // Refills buffer_ from the file; false at the end.
  bool fill();

  std::string path_;
  std::FILE* file_ = nullptr;
  void* bz_ = nullptr;  // BZFILE*
  std::vector<char> buffer_;
  size_t begin_ = 0;
  size_t end_ = 0;
  bool eof_ = false;
  long lineNumber_ = 0;
};

// Splits on blanks (and commas when `commas`), dropping empty fields.
std::vector<std::string_view> splitFields(std::string_view line, bool commas = false);
// Blank line, or first non-blank character '#'.
bool isCommentOrBlank(std::string_view line);
// Parses a finite number; throws "path:line: <what>: 'token' is not a number".
double parseNumber(std::string_view token, const std::string& path, long line, const char* what);
long long parseInteger(std::string_view token, const std::string& path, long line, const char* what);
// Same without context: false if not a finite number / integer.
bool tryParseNumber(std::string_view token, double& value);
bool tryParseInteger(std::string_view token, long long& value);

bool isDirectory(const std::string& path);
bool isFile(const std::string& path);
std::string joinPath(const std::string& a, const std::string& b);
std::string fileName(const std::string& path);
std::string toLower(std::string s);
// Compares names with runs of digits as numbers: "2.jpg" < "10.jpg" (then lexicographic).
bool naturalLess(const std::string& a, const std::string& b);
// Regular files of a folder whose lower-case extension is one of `extensions` (".png", ...;
// empty = all), names only, in natural order.
std::vector<std::string> listFiles(const std::string& dir, const std::vector<std::string>& extensions);
// cv::imread with IMREAD_UNCHANGED (or the given flags); FormatError naming the file if it
// cannot be read.
cv::Mat readImage(const std::string& path, int flags = -1);

// The frame window of DatasetReaderOptions (startFrame, maxFrames) over a time-ordered record
// stream. Non-frame records (IMU, odometry) between the last skipped frame and the first kept
// one are kept (so an IMU integrator has the samples leading to the first frame); the stream
// ends right after the last kept frame.
class WindowedReader : public DatasetReader {
 public:
  bool next(DatasetRecord& record) final;

 protected:
  explicit WindowedReader(const DatasetReaderOptions& options) : options_(options) {}
  // The next record of the whole dataset, in time order; false at its end.
  virtual bool readNext(DatasetRecord& record) = 0;
  // True when the next frame readNext() yields falls before startFrame and will be dropped:
  // the reader may skip loading its payload.
  bool nextFrameSkipped() const { return framesRead_ < options_.startFrame; }
  // Frames in the window out of `total` frames in the dataset.
  int windowed(int total) const;
  const DatasetReaderOptions& options() const { return options_; }

 private:
  DatasetReaderOptions options_;
  std::deque<DatasetRecord> pending_;  // non-frame records after the last skipped frame
  std::deque<DatasetRecord> ready_;
  int framesRead_ = 0;
  int framesKept_ = 0;
  bool done_ = false;
};

// Poses of a text file holding one 3x4 row-major matrix per row (KITTI poses; blanks or
// commas). Row n (0-based) is frame n.
std::vector<Transform> readPoseRows(const std::string& path);

}  // namespace rtabmap::eval_detail
