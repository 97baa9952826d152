#include "rtabmap_core/sim/PngWriter.h"

#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "rtabmap_core/common/Error.h"

namespace rtabmap::sim {

namespace {

void putBigEndian(std::vector<uint8_t>& out, uint32_t v) {
  out.push_back(static_cast<uint8_t>(v >> 24));
  out.push_back(static_cast<uint8_t>(v >> 16));
  out.push_back(static_cast<uint8_t>(v >> 8));
  out.push_back(static_cast<uint8_t>(v));
}

// A PNG chunk: length, type, data, CRC-32 of type and data.
void putChunk(std::vector<uint8_t>& out, const char* type, const uint8_t* data, size_t size) {
  putBigEndian(out, static_cast<uint32_t>(size));
  const size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  if (size) out.insert(out.end(), data, data + size);
  putBigEndian(out, static_cast<uint32_t>(crc32(0L, out.data() + start, static_cast<uInt>(size + 4))));
}

inline int magnitude(uint8_t residual) {
  const int v = static_cast<int8_t>(residual);
  return v < 0 ? -v : v;
}

}  // namespace

std::vector<uint8_t> encodePng(const cv::Mat& image) {
  const int type = image.type();
  if (type != CV_8UC1 && type != CV_8UC3 && type != CV_16UC1) {
    throw std::invalid_argument("encodePng: expected CV_8UC1, CV_8UC3 or CV_16UC1");
  }
  const int channels = image.channels();
  const int sampleBytes = static_cast<int>(image.elemSize1());
  const int pixelBytes = channels * sampleBytes;
  const size_t rowBytes = static_cast<size_t>(image.cols) * pixelBytes;

  // Filtered rows: a filter-type byte, then the residuals.
  std::vector<uint8_t> filtered((rowBytes + 1) * static_cast<size_t>(image.rows));
  std::vector<uint8_t> row(rowBytes), previous(rowBytes, 0), sub(rowBytes), up(rowBytes);
  for (int y = 0; y < image.rows; ++y) {
    const uint8_t* p = image.ptr<uint8_t>(y);
    if (type == CV_8UC3) {
      for (int x = 0; x < image.cols; ++x) {  // PNG stores RGB
        row[3 * x] = p[3 * x + 2];
        row[3 * x + 1] = p[3 * x + 1];
        row[3 * x + 2] = p[3 * x];
      }
    } else if (type == CV_16UC1) {
      const uint16_t* q = image.ptr<uint16_t>(y);
      for (int x = 0; x < image.cols; ++x) {  // PNG stores 16-bit samples big-endian
        row[2 * x] = static_cast<uint8_t>(q[x] >> 8);
        row[2 * x + 1] = static_cast<uint8_t>(q[x]);
      }
    } else {
      std::memcpy(row.data(), p, rowBytes);
    }
    long costSub = 0, costUp = 0;
    for (size_t i = 0; i < rowBytes; ++i) {
      const uint8_t left = i >= static_cast<size_t>(pixelBytes) ? row[i - pixelBytes] : 0;
      sub[i] = static_cast<uint8_t>(row[i] - left);
      up[i] = static_cast<uint8_t>(row[i] - previous[i]);
      costSub += magnitude(sub[i]);
      costUp += magnitude(up[i]);
    }
    uint8_t* out = &filtered[static_cast<size_t>(y) * (rowBytes + 1)];
    const bool useUp = costUp < costSub;
    out[0] = useUp ? 2 : 1;  // PNG filter types: 1 Sub, 2 Up
    std::memcpy(out + 1, useUp ? up.data() : sub.data(), rowBytes);
    std::swap(previous, row);
  }

  std::vector<uint8_t> compressed(compressBound(static_cast<uLong>(filtered.size())));
  z_stream zs;
  std::memset(&zs, 0, sizeof(zs));
  if (deflateInit2(&zs, 1, Z_DEFLATED, 15, 8, Z_RLE) != Z_OK) throw std::runtime_error("encodePng: zlib init failed");
  zs.next_in = filtered.data();
  zs.avail_in = static_cast<uInt>(filtered.size());
  zs.next_out = compressed.data();
  zs.avail_out = static_cast<uInt>(compressed.size());
  const int rc = deflate(&zs, Z_FINISH);
  const size_t compressedSize = zs.total_out;
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw std::runtime_error("encodePng: zlib failed");

  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  std::vector<uint8_t> header;
  putBigEndian(header, static_cast<uint32_t>(image.cols));
  putBigEndian(header, static_cast<uint32_t>(image.rows));
  header.push_back(static_cast<uint8_t>(8 * sampleBytes));  // bit depth
  header.push_back(channels == 3 ? 2 : 0);                   // colour type: RGB or grey
  header.push_back(0);                                        // deflate
  header.push_back(0);                                        // adaptive filtering (per row)
  header.push_back(0);                                        // no interlace
  putChunk(png, "IHDR", header.data(), header.size());
  putChunk(png, "IDAT", compressed.data(), compressedSize);
  putChunk(png, "IEND", nullptr, 0);
  return png;
}

void writePng(const std::string& path, const cv::Mat& image) {
  const std::vector<uint8_t> png = encodePng(image);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw Error("cannot write " + path + ": " + std::strerror(errno));
  const bool ok = std::fwrite(png.data(), 1, png.size(), f) == png.size();
  if (std::fclose(f) != 0 || !ok) throw Error("cannot write " + path + " (disk full?)");
}

}  // namespace rtabmap::sim
