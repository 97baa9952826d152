// The 2D grid as files: map_server PGM + YAML (both ways) and a PNG preview (see MapIO.h).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/maps/MapIO.h"

namespace rtabmap {

namespace fs = std::filesystem;

namespace {
// map_saver's pixel values: they read back unambiguously with thresholds 0.65 / 0.196.
constexpr uchar kPgmOccupied = 0;
constexpr uchar kPgmFree = 254;
constexpr uchar kPgmUnknown = 205;
constexpr double kOccupiedThresh = 0.65;
constexpr double kFreeThresh = 0.196;

cv::Mat toImage(const GridMap& map, uchar occupied, uchar free, uchar unknown) {
  if (map.empty()) throw FormatError("cannot write an empty map");
  cv::Mat image(map.height(), map.width(), CV_8UC1);
  for (int r = 0; r < map.height(); ++r) {
    const int8_t* src = map.data.ptr<int8_t>(r);
    uchar* dst = image.ptr<uchar>(map.height() - 1 - r);  // the image's top row is the highest y
    for (int c = 0; c < map.width(); ++c) {
      dst[c] = src[c] == GridMap::kOccupied ? occupied : (src[c] == GridMap::kFree ? free : unknown);
    }
  }
  return image;
}
}  // namespace

cv::Mat gridToPgmImage(const GridMap& map) { return toImage(map, kPgmOccupied, kPgmFree, kPgmUnknown); }

void writeMapServer(const GridMap& map, const std::string& pgmPath, const std::string& yamlPath) {
  const cv::Mat image = gridToPgmImage(map);
  bool written = false;
  try {
    written = cv::imwrite(pgmPath, image);
  } catch (const cv::Exception& e) {
    throw FormatError("cannot write " + pgmPath + ": " + e.what());
  }
  if (!written) throw FormatError("cannot write " + pgmPath);
  std::ofstream yaml(yamlPath);
  if (!yaml) throw FormatError("cannot write " + yamlPath);
  // The image path is relative to the YAML's folder, as map_server resolves it.
  const fs::path rel = fs::path(pgmPath).lexically_proximate(fs::path(yamlPath).parent_path().empty()
                                                                  ? fs::path(".")
                                                                  : fs::path(yamlPath).parent_path());
  // Resolution with a float's significant digits (0.05, not 0.0500000007); origin to the
  // micrometre.
  yaml << "image: " << rel.string() << "\n"
       << "mode: trinary\n"
       << "resolution: " << std::setprecision(7) << map.resolution << "\n"
       << std::fixed << std::setprecision(6) << "origin: [" << map.originX << ", " << map.originY
       << ", 0.0]\n" << std::defaultfloat
       << "negate: 0\n"
       << "occupied_thresh: " << kOccupiedThresh << "\n"
       << "free_thresh: " << kFreeThresh << "\n";
  if (!yaml) throw FormatError("cannot write " + yamlPath);
}

GridMap readMapServer(const std::string& yamlPath) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(yamlPath);
  } catch (const YAML::Exception& e) {
    throw FormatError("cannot read map YAML " + yamlPath + ": " + e.what());
  }
  auto need = [&](const char* key) {
    if (!doc[key]) throw FormatError("map YAML " + yamlPath + " has no '" + std::string(key) + "'");
    return doc[key];
  };
  GridMap map;
  std::string image;
  double occupiedThresh = 0, freeThresh = 0;
  int negate = 0;
  try {
    image = need("image").as<std::string>();
    map.resolution = need("resolution").as<float>();
    const YAML::Node origin = need("origin");
    if (!origin.IsSequence() || origin.size() < 2) throw FormatError("map YAML " + yamlPath + ": origin must be [x, y, yaw]");
    map.originX = origin[0].as<double>();
    map.originY = origin[1].as<double>();
    if (origin.size() >= 3 && std::abs(origin[2].as<double>()) > 1e-9) {
      throw FormatError("map YAML " + yamlPath + ": a rotated origin (yaw != 0) is not supported");
    }
    negate = need("negate").as<int>();
    occupiedThresh = need("occupied_thresh").as<double>();
    freeThresh = need("free_thresh").as<double>();
  } catch (const YAML::Exception& e) {
    throw FormatError("map YAML " + yamlPath + ": " + e.what());
  }
  if (!(map.resolution > 0.0f)) throw FormatError("map YAML " + yamlPath + ": resolution must be > 0");
  fs::path imagePath(image);
  if (imagePath.is_relative()) imagePath = fs::path(yamlPath).parent_path() / imagePath;
  const cv::Mat pixels = cv::imread(imagePath.string(), cv::IMREAD_GRAYSCALE);
  if (pixels.empty()) throw FormatError("cannot read map image " + imagePath.string() + " (from " + yamlPath + ")");
  map.data = cv::Mat(pixels.rows, pixels.cols, CV_8SC1);
  for (int r = 0; r < pixels.rows; ++r) {
    const uchar* src = pixels.ptr<uchar>(pixels.rows - 1 - r);
    int8_t* dst = map.data.ptr<int8_t>(r);
    for (int c = 0; c < pixels.cols; ++c) {
      const double occ = negate ? src[c] / 255.0 : (255.0 - src[c]) / 255.0;
      dst[c] = occ > occupiedThresh ? GridMap::kOccupied : (occ < freeThresh ? GridMap::kFree : GridMap::kUnknown);
    }
  }
  return map;
}

void writeGridPng(const GridMap& map, const std::string& pngPath, int scale) {
  cv::Mat image = toImage(map, 0, 255, 160);
  if (scale > 1) cv::resize(image, image, cv::Size(), scale, scale, cv::INTER_NEAREST);
  bool written = false;
  try {
    written = cv::imwrite(pngPath, image);
  } catch (const cv::Exception& e) {
    throw FormatError("cannot write " + pngPath + ": " + e.what());
  }
  if (!written) throw FormatError("cannot write " + pngPath);
}

}  // namespace rtabmap
