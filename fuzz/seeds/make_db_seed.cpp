// Writes a small but complete database (3 nodes with words, links, compressed image, depth and
// scan, statistics-free) as the seed of the `database` fuzz target: the real datasets hold no
// database, and a seed of a few pages lets libFuzzer mutate every table's records quickly.
// Also writes the codec target's own blobs (compressData / compressBytes headers).
//   make_db_seed <output.db> <codec-corpus-dir>
#include <opencv2/core.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "rtabmap_core/codec/Compression.h"
#include "rtabmap_core/db/Database.h"
#include "rtabmap_core/memory/Signature.h"
#include "rtabmap_core/params/Parameters.h"

namespace {

rtabmap::Signature seedNode(int id) {
  using namespace rtabmap;
  Signature node(id, 0, 1, 10.0 + id, id == 2 ? "door" : "", Transform(0.5 * id, 0.0, 0.0, 0.0, 0.0, 0.1 * id));
  std::multimap<int, int> words;
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point3f> points;
  for (int i = 0; i < 4; ++i) {
    words.emplace(id * 10 + i, i);
    keypoints.emplace_back(4.0f * i, 3.0f * i, 31.0f);
    points.emplace_back(0.1f * i, 0.2f, 1.0f);
  }
  node.setWords(words, keypoints, points, cv::Mat(4, 32, CV_8UC1, cv::Scalar(id)));
  SensorData data(cv::Mat(), cv::Mat(), CameraModel(525.0, 525.0, 4.0, 3.0, CameraModel::opticalRotation(), 0.0, cv::Size(8, 6)),
                  id, node.stamp());
  data.setCompressed(codec::compressImage(cv::Mat(6, 8, CV_8UC3, cv::Scalar(id, 2, 3)), ".png"),
                     codec::compressDepth(cv::Mat(6, 8, CV_16UC1, cv::Scalar(1000 + id))),
                     codec::compressData(cv::Mat(1, 5, CV_32FC2, cv::Scalar(1.0f, 2.0f))), {});
  node.setSensorData(data);
  if (id > 1) {
    node.addLink(Link(id, id - 1, Link::kNeighbor, Transform(-0.5, 0.0, 0.0, 0.0, 0.0, -0.1),
                      Link::InfMatrix::Identity() * 100.0));
  }
  return node;
}

void writeBlob(const std::filesystem::path& path, const rtabmap::Bytes& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

void writeCodecSeeds(const std::filesystem::path& dir) {
  using namespace rtabmap::codec;
  std::filesystem::create_directories(dir);
  cv::Mat depth(6, 8, CV_32FC1);
  cv::randu(depth, 0.0f, 5.0f);
  writeBlob(dir / "rtz_depth32f.bin", compressData(depth));
  writeBlob(dir / "rtz_scan.bin", compressData(cv::Mat(1, 7, CV_32FC3, cv::Scalar(1, 2, 3))));
  writeBlob(dir / "png_depth16u.bin", compressDepth(cv::Mat(6, 8, CV_16UC1, cv::Scalar(1234))));
  const std::string text = "Kp/MaxFeatures=400;Vis/MinInliers=20";
  writeBlob(dir / "rtb_bytes.bin", compressBytes(rtabmap::Bytes(text.begin(), text.end())));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_db_seed <output.db> <codec-corpus-dir>\n";
    return 2;
  }
  writeCodecSeeds(argv[2]);
  std::filesystem::remove(argv[1]);
  rtabmap::db::DatabaseOptions options;
  options.pageSize = 512;                                     // a few small pages to mutate
  options.journalMode = rtabmap::db::DatabaseOptions::JournalMode::kDelete;  // one file, no WAL
  options.sessionParameters = rtabmap::Parameters::serialize({{"Kp/MaxFeatures", "400"}});
  rtabmap::db::Database database(argv[1], options);
  for (int id = 1; id <= 3; ++id) {
    std::vector<rtabmap::db::StoredWord> words;
    for (int i = 0; i < 4; ++i) words.push_back({id * 10 + i, cv::Mat(1, 32, CV_8UC1, cv::Scalar(i))});
    database.saveNode(seedNode(id), words);
  }
  database.close();
  return 0;
}
