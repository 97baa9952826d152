// "images": a folder of images (jpg, jpeg, png, bmp, pgm, ppm, tif, tiff), one frame each, in
// natural name order (2.jpg before 10.jpg; image_9.png before image_10.png), for
// appearance-only loop closure (rtabmap-console). Frame k (0-based) has id k + 1 (the ids of
// loop-closure detection files, see LoopClosureEval.h) and stamp k / rate, the rate being
// DatasetReaderOptions::frameRate or 1 Hz: the folder has no times, and 1 Hz is the usual
// detection rate of appearance-only runs. Images are loaded as they are stored (grey stays
// grey, colour is BGR, an alpha channel is dropped). No camera model, unless calibrationPath
// gives a ROS camera_info YAML.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <memory>
#include <string>
#include <vector>

#include "ReaderSupport.h"
#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/eval/DatasetReader.h"
#include "rtabmap_core/geometry/CameraModel.h"

namespace rtabmap {
namespace {

class ImageFolderReader : public eval_detail::WindowedReader {
 public:
  ImageFolderReader(const std::string& path, const DatasetReaderOptions& options)
      : WindowedReader(options), path_(path) {
    if (!eval_detail::isDirectory(path)) throw FormatError("images: " + path + " is not a folder");
    names_ = eval_detail::listFiles(
        path, {".jpg", ".jpeg", ".png", ".bmp", ".pgm", ".ppm", ".tif", ".tiff"});
    if (names_.empty()) {
      throw FormatError("images: " + path + " holds no image (jpg, jpeg, png, bmp, pgm, ppm, tif, tiff)");
    }
    rate_ = options.frameRate > 0.0 ? options.frameRate : 1.0;
    if (!options.calibrationPath.empty()) models_.push_back(CameraModel::load(options.calibrationPath));
  }

  std::string format() const override { return "images"; }
  int frameCount() const override { return windowed(static_cast<int>(names_.size())); }

 protected:
  bool readNext(DatasetRecord& record) override {
    if (cursor_ >= names_.size()) return false;
    const size_t i = cursor_++;
    record = DatasetRecord();
    record.kind = DatasetRecord::Kind::kFrame;
    record.stamp = static_cast<double>(i) / rate_;
    if (nextFrameSkipped()) return true;
    cv::Mat image;
    if (options().images) {
      image = eval_detail::readImage(eval_detail::joinPath(path_, names_[i]), cv::IMREAD_UNCHANGED);
      if (image.depth() != CV_8U) {
        throw FormatError(eval_detail::joinPath(path_, names_[i]) + ": expected an 8-bit image");
      }
      if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
    }
    record.data = SensorData(image, cv::Mat(), models_, static_cast<int>(i) + 1, record.stamp);
    return true;
  }

 private:
  std::string path_;
  std::vector<std::string> names_;
  std::vector<CameraModel> models_;
  double rate_ = 1.0;
  size_t cursor_ = 0;
};

[[maybe_unused]] const bool kRegistered = registerDatasetFormat(
    "images", [](const std::string& path, const DatasetReaderOptions& options) {
      return std::unique_ptr<DatasetReader>(new ImageFolderReader(path, options));
    });

}  // namespace
}  // namespace rtabmap
