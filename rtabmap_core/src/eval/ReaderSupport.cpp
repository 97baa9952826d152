#include "ReaderSupport.h"

#include <bzlib.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "rtabmap_core/common/Error.h"

namespace fs = std::filesystem;

namespace rtabmap::eval_detail {

void throwAt(const std::string& path, long line, const std::string& message) {
  throw FormatError(path + ":" + std::to_string(line) + ": " + message);
}

// ---------------------------------------------------------------------------------------------
// TextLineReader
// ---------------------------------------------------------------------------------------------

namespace {
constexpr size_t kChunk = 1 << 16;

const char* bzErrorName(int code) {
  switch (code) {
    case BZ_DATA_ERROR:
      return "corrupt data (CRC or structure error)";
    case BZ_DATA_ERROR_MAGIC:
      return "not bzip2 data";
    case BZ_UNEXPECTED_EOF:
      return "truncated file (ends inside a compressed block)";
    case BZ_MEM_ERROR:
      return "out of memory";
    case BZ_IO_ERROR:
      return "read error";
    default:
      return "bzip2 error";
  }
}
}  // namespace

TextLineReader::TextLineReader(const std::string& path) : path_(path) {
  if (isDirectory(path)) throw FormatError(path + ": is a folder, expected a text file");
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) throw FormatError(path + ": cannot open (" + std::strerror(errno) + ")");
  unsigned char magic[3] = {0, 0, 0};
  const size_t n = std::fread(magic, 1, 3, file_);
  std::rewind(file_);
  if (n == 3 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h') {
    int err = BZ_OK;
    bz_ = BZ2_bzReadOpen(&err, file_, 0, 0, nullptr, 0);
    if (err != BZ_OK) {
      BZ2_bzReadClose(&err, bz_);
      bz_ = nullptr;
      std::fclose(file_);
      file_ = nullptr;
      throw FormatError(path + ": cannot start bzip2 decompression");
    }
  }
  buffer_.resize(kChunk);
}

TextLineReader::~TextLineReader() {
  if (bz_) {
    int err = BZ_OK;
    BZ2_bzReadClose(&err, bz_);
  }
  if (file_) std::fclose(file_);
}

bool TextLineReader::fill() {
  if (eof_) return false;
  // Keep the unconsumed tail at the front.
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  if (buffer_.size() - end_ < kChunk / 2) buffer_.resize(buffer_.size() * 2);
  char* dst = buffer_.data() + end_;
  const int room = static_cast<int>(std::min<size_t>(buffer_.size() - end_, 1 << 30));
  if (!bz_) {
    const size_t n = std::fread(dst, 1, static_cast<size_t>(room), file_);
    if (n == 0) {
      if (std::ferror(file_)) throw FormatError(path_ + ": read error");
      eof_ = true;
      return false;
    }
    end_ += n;
    return true;
  }
  while (true) {
    int err = BZ_OK;
    const int n = BZ2_bzRead(&err, bz_, dst, room);
    if (err == BZ_OK) {
      if (n > 0) {
        end_ += static_cast<size_t>(n);
        return true;
      }
      continue;
    }
    if (err != BZ_STREAM_END) {
      throw FormatError(path_ + ": bzip2: " + bzErrorName(err) + " after line " +
                        std::to_string(lineNumber_));
    }
    // End of one stream: another may follow (concatenated streams).
    void* unusedPtr = nullptr;
    int nUnused = 0;
    BZ2_bzReadGetUnused(&err, bz_, &unusedPtr, &nUnused);
    std::vector<char> unused(static_cast<char*>(unusedPtr), static_cast<char*>(unusedPtr) + nUnused);
    BZ2_bzReadClose(&err, bz_);
    bz_ = nullptr;
    bool more = nUnused > 0;
    if (!more) {
      const int c = std::fgetc(file_);
      if (c != EOF) {
        std::ungetc(c, file_);
        more = true;
      }
    }
    if (!more) {
      eof_ = true;
      // Keep compressed() true for the caller's information? Not needed past the end.
      end_ += static_cast<size_t>(n);
      return n > 0;
    }
    bz_ = BZ2_bzReadOpen(&err, file_, 0, 0, unused.empty() ? nullptr : unused.data(),
                         static_cast<int>(unused.size()));
    if (err != BZ_OK) throw FormatError(path_ + ": bzip2: cannot read the next stream");
    if (n > 0) {
      end_ += static_cast<size_t>(n);
      return true;
    }
  }
}

bool TextLineReader::next(std::string& line) {
  while (true) {
    const char* start = buffer_.data() + begin_;
    const void* nl = std::memchr(start, '\n', end_ - begin_);
    if (nl) {
      const size_t len = static_cast<const char*>(nl) - start;
      line.assign(start, len);
      begin_ += len + 1;
      break;
    }
    if (!fill()) {
      if (begin_ == end_) return false;
      line.assign(buffer_.data() + begin_, end_ - begin_);  // last line without newline
      begin_ = end_;
      break;
    }
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  ++lineNumber_;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Parsing
// ---------------------------------------------------------------------------------------------

std::vector<std::string_view> splitFields(std::string_view line, bool commas) {
  std::vector<std::string_view> out;
  size_t i = 0;
  const size_t n = line.size();
  auto isSep = [commas](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' ||
           (commas && c == ',');
  };
  while (i < n) {
    while (i < n && isSep(line[i])) ++i;
    const size_t b = i;
    while (i < n && !isSep(line[i])) ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

bool isCommentOrBlank(std::string_view line) {
  for (char c : line) {
    // Fuzzing fix (fuzz/regressions/{trajectory,carmen}): blank means every separator
    // splitFields() skips, '\v' and '\f' included; a line of only those used to pass as
    // non-blank and split into no field, and readers then read fields[0] out of bounds.
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f') continue;
    return c == '#';
  }
  return true;
}

bool tryParseNumber(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size() || !std::isfinite(v)) return false;
  value = v;
  return true;
}

bool tryParseInteger(std::string_view token, long long& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  long long v = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size()) return false;
  value = v;
  return true;
}

double parseNumber(std::string_view token, const std::string& path, long line, const char* what) {
  double v = 0.0;
  if (!tryParseNumber(token, v)) {
    throwAt(path, line, std::string(what) + ": '" + std::string(token) + "' is not a finite number");
  }
  return v;
}

long long parseInteger(std::string_view token, const std::string& path, long line, const char* what) {
  long long v = 0;
  if (!tryParseInteger(token, v)) {
    throwAt(path, line, std::string(what) + ": '" + std::string(token) + "' is not an integer");
  }
  return v;
}

// ---------------------------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------------------------

bool isDirectory(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

bool isFile(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string joinPath(const std::string& a, const std::string& b) {
  return (fs::path(a) / b).string();
}

std::string fileName(const std::string& path) { return fs::path(path).filename().string(); }

std::string toLower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool naturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])) != 0;
    const bool db = std::isdigit(static_cast<unsigned char>(b[j])) != 0;
    if (da && db) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      // Compare the runs as numbers: skip leading zeros, then length, then digits.
      size_t is = i, js = j;
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      const size_t la = ie - is, lb = je - js;
      if (la != lb) return la < lb;
      const int c = a.compare(is, la, b, js, lb);
      if (c != 0) return c < 0;
      // Same value: fewer leading zeros first, for a strict order.
      if ((ie - i) != (je - j)) return (ie - i) < (je - j);
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  return (a.size() - i) < (b.size() - j);
}

std::vector<std::string> listFiles(const std::string& dir, const std::vector<std::string>& extensions) {
  std::vector<std::string> names;
  std::error_code ec;
  fs::directory_iterator it(dir, ec);
  if (ec) throw FormatError(dir + ": cannot list the folder (" + ec.message() + ")");
  for (const auto& entry : it) {
    std::error_code ec2;
    if (!entry.is_regular_file(ec2)) continue;
    const std::string name = entry.path().filename().string();
    if (!extensions.empty()) {
      const std::string ext = toLower(entry.path().extension().string());
      if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) continue;
    }
    names.push_back(name);
  }
  std::sort(names.begin(), names.end(), naturalLess);
  return names;
}

cv::Mat readImage(const std::string& path, int flags) {
  if (!isFile(path)) throw FormatError(path + ": image file missing");
  cv::Mat image = cv::imread(path, flags);
  if (image.empty()) throw FormatError(path + ": cannot decode the image");
  return image;
}

// ---------------------------------------------------------------------------------------------
// WindowedReader
// ---------------------------------------------------------------------------------------------

bool WindowedReader::next(DatasetRecord& record) {
  while (ready_.empty() && !done_) {
    DatasetRecord r;
    if (!readNext(r)) {
      done_ = true;
      pending_.clear();
      break;
    }
    if (r.kind == DatasetRecord::Kind::kFrame) {
      const int index = framesRead_++;
      if (index < options_.startFrame) {
        pending_.clear();
        continue;
      }
      for (auto& p : pending_) ready_.push_back(std::move(p));
      pending_.clear();
      ready_.push_back(std::move(r));
      ++framesKept_;
      if (options_.maxFrames > 0 && framesKept_ >= options_.maxFrames) done_ = true;
    } else if (framesRead_ < options_.startFrame) {
      pending_.push_back(std::move(r));
    } else {
      ready_.push_back(std::move(r));
    }
  }
  if (ready_.empty()) return false;
  record = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

int WindowedReader::windowed(int total) const {
  int n = std::max(0, total - std::max(0, options_.startFrame));
  if (options_.maxFrames > 0) n = std::min(n, options_.maxFrames);
  return n;
}

std::vector<Transform> readPoseRows(const std::string& path) {
  TextLineReader in(path);
  std::vector<Transform> poses;
  std::string line;
  while (in.next(line)) {
    if (isCommentOrBlank(line)) continue;
    const auto f = splitFields(line, true);
    if (f.size() != 12) {
      throwAt(path, in.lineNumber(),
              "expected 12 numbers (a 3x4 pose, row-major), got " + std::to_string(f.size()));
    }
    double v[12];
    for (int i = 0; i < 12; ++i) v[i] = parseNumber(f[i], path, in.lineNumber(), "pose value");
    poses.push_back(Transform::fromArray12(v));
  }
  return poses;
}

}  // namespace rtabmap::eval_detail
