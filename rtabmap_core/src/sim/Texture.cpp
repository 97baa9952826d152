#include "rtabmap_core/sim/Texture.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <stdexcept>
#include <string>

namespace rtabmap::sim {

namespace {

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Halves an image with a box filter. For a wrapping texture both sizes are even, so every
// output texel is the plain mean of four; a decal's odd size rounds up (INTER_AREA weights the
// last row/column in).
cv::Mat halve(const cv::Mat& image) {
  const int w = std::max(1, (image.cols + 1) / 2);
  const int h = std::max(1, (image.rows + 1) / 2);
  cv::Mat out;
  cv::resize(image, out, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace

Texture::Texture(const cv::Mat& image, bool wrap, float texelsPerMetre)
    : Texture(std::vector<cv::Mat>{image}, wrap, texelsPerMetre) {}

Texture::Texture(const std::vector<cv::Mat>& variants, bool wrap, float texelsPerMetre, uint32_t salt)
    : salt_(salt), wrap_(wrap), texelsPerMetre_(texelsPerMetre) {
  if (variants.empty()) throw std::invalid_argument("Texture: no picture");
  if (variants.size() > 1 && !wrap) throw std::invalid_argument("Texture: only a wrapping texture has tile variants");
  for (const cv::Mat& image : variants) {
    if (image.empty() || image.type() != CV_8UC3) {
      throw std::invalid_argument("Texture: expected a non-empty CV_8UC3 image");
    }
    if (image.size() != variants.front().size()) throw std::invalid_argument("Texture: variants of different sizes");
  }
  const cv::Mat& image = variants.front();
  if (wrap && (!isPowerOfTwo(image.cols) || !isPowerOfTwo(image.rows))) {
    throw std::invalid_argument("Texture: a wrapping texture needs power-of-two sizes, got " +
                                std::to_string(image.cols) + "x" + std::to_string(image.rows));
  }
  if (!(texelsPerMetre > 0.0f)) throw std::invalid_argument("Texture: texelsPerMetre must be > 0");
  for (const cv::Mat& variant : variants) {
    std::vector<cv::Mat> pictures = {variant};
    while (pictures.back().cols > 1 || pictures.back().rows > 1) pictures.push_back(halve(pictures.back()));
    levelCount_ = static_cast<int>(pictures.size());
    for (const cv::Mat& m : pictures) {
      cv::Mat transposed;
      cv::transpose(m, transposed);
      levels_.push_back(transposed);
      TextureLevel v;
      v.data = transposed.data;
      v.width = m.cols;
      v.height = m.rows;
      v.step = transposed.step[0];
      v.scaleX = static_cast<float>(m.cols) / static_cast<float>(image.cols);
      v.scaleY = static_cast<float>(m.rows) / static_cast<float>(image.rows);
      v.wrap = wrap;
      if (wrap) {
        while ((1 << v.shiftX) < m.cols) ++v.shiftX;
        while ((1 << v.shiftY) < m.rows) ++v.shiftY;
      }
      views_.push_back(v);
    }
  }
  variantCount_ = static_cast<int>(variants.size());
  const cv::Scalar mean = cv::mean(image);
  meanGrey_ = static_cast<float>(0.114 * mean[0] + 0.587 * mean[1] + 0.299 * mean[2]);
}

cv::Mat Texture::image(int level, int variant) const {
  if (level < 0 || level >= levelCount_ || variant < 0 || variant >= variantCount_) {
    throw std::out_of_range("Texture::image: no such level or variant");
  }
  cv::Mat picture;
  cv::transpose(levels_[static_cast<size_t>(variant * levelCount_ + level)], picture);
  return picture;
}

}  // namespace rtabmap::sim
