#include "rtabmap_core/sim/Decals.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

#include "rtabmap_core/sim/Procedural.h"
#include "rtabmap_core/sim/Random.h"

namespace rtabmap::sim {

namespace {

constexpr int kLine = cv::LINE_AA;

cv::Scalar scalar(const cv::Vec3f& c) { return cv::Scalar(c[0], c[1], c[2]); }
// Draws happen in statement order: a function's arguments are evaluated in an unspecified
// order, and another compiler would then paint other pictures from the same seed.
cv::Vec3f randomHsv(Rng& rng, double h0, double h1, double s0, double s1, double v0, double v1) {
  const float h = static_cast<float>(rng.uniform(h0, h1));
  const float s = static_cast<float>(rng.uniform(s0, s1));
  const float v = static_cast<float>(rng.uniform(v0, v1));
  return hsv(h, s, v);
}
cv::Scalar randomColour(Rng& rng, double s0 = 0.3, double s1 = 0.9, double v0 = 0.3, double v1 = 0.95) {
  return scalar(randomHsv(rng, 0, 360, s0, s1, v0, v1));
}
// Black or white, whichever reads on that background.
cv::Scalar contrasting(const cv::Scalar& background) {
  const double luma = 0.114 * background[0] + 0.587 * background[1] + 0.299 * background[2];
  return luma > 128 ? cv::Scalar(20, 20, 20) : cv::Scalar(245, 245, 245);
}

// Text fitted into a box: the Hershey scale that makes `text` as wide as `width` pixels (or as
// tall as maxHeight), drawn left-aligned with its baseline at `origin`.
void fitText(cv::Mat& img, const std::string& text, cv::Point origin, int width, int maxHeight,
             int font, const cv::Scalar& colour) {
  int baseline = 0;
  const cv::Size unit = cv::getTextSize(text, font, 1.0, 1, &baseline);
  double scale = static_cast<double>(width) / std::max(1, unit.width);
  if (unit.height * scale > maxHeight) scale = static_cast<double>(maxHeight) / std::max(1, unit.height);
  const int thickness = std::max(1, static_cast<int>(std::lround(scale * 1.6)));
  cv::putText(img, text, origin, font, scale, colour, thickness, kLine);
}

// Lines of small random words from y0 down, until y1, inside [x0, x1].
void paragraph(cv::Mat& img, Rng& rng, int x0, int x1, int y0, int y1, int lineHeight, const cv::Scalar& colour) {
  const double scale = lineHeight / 30.0;  // Hershey simplex: about 22 px tall at scale 1
  for (int y = y0 + lineHeight; y <= y1; y += static_cast<int>(lineHeight * 1.5)) {
    int x = x0;
    while (x < x1) {
      const std::string word = randomWord(rng, 2, 8);
      int baseline = 0;
      const cv::Size size = cv::getTextSize(word, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
      if (x + size.width > x1) break;
      cv::putText(img, word, cv::Point(x, y), cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, kLine);
      x += size.width + std::max(2, lineHeight / 2);
    }
    if (rng.chance(0.15)) y += lineHeight;  // paragraph break
  }
}

// A soft fractal field of colours (photos, paintings, skies).
void noiseField(cv::Mat& img, cv::Rect area, uint32_t seed, const cv::Vec3f& a, const cv::Vec3f& b,
                float cells) {
  area &= cv::Rect(0, 0, img.cols, img.rows);
  for (int y = area.y; y < area.y + area.height; ++y) {
    cv::Vec3b* row = img.ptr<cv::Vec3b>(y);
    for (int x = area.x; x < area.x + area.width; ++x) {
      const float n = fbm(x / cells, y / cells, 4, 1 << 20, 1 << 20, seed);
      row[x] = toBgr8(mixColour(a, b, n));
    }
  }
}

void poster(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  const cv::Scalar background = randomColour(rng, 0.1, 0.8, 0.3, 0.95);
  img.setTo(background);
  const int shapes = rng.uniformInt(2, 6);
  for (int i = 0; i < shapes; ++i) {
    const cv::Scalar c = randomColour(rng);
    const cv::Point centre{rng.uniformInt(0, w), rng.uniformInt(h / 4, h)};  // braces: left to right
    const int r = rng.uniformInt(w / 10, w / 3);
    switch (rng.uniformInt(0, 2)) {
      case 0: cv::circle(img, centre, r, c, cv::FILLED, kLine); break;
      case 1: cv::rectangle(img, cv::Rect(centre.x - r, centre.y - r / 2, 2 * r, r), c, cv::FILLED, kLine); break;
      default: {
        std::vector<cv::Point> tri = {centre + cv::Point(0, -r), centre + cv::Point(r, r), centre + cv::Point(-r, r)};
        cv::fillConvexPoly(img, tri, c, kLine);
      }
    }
  }
  if (rng.chance(0.5)) {  // a "photo"
    const cv::Rect photo(w / 8, h / 3, w * 3 / 4, h / 3);
    const uint32_t seed = rng.seed32();
    const cv::Vec3f light = randomHsv(rng, 0, 360, 0.6, 0.6, 0.8, 0.8);
    const cv::Vec3f dark = randomHsv(rng, 0, 360, 0.7, 0.7, 0.3, 0.3);
    noiseField(img, photo, seed, light, dark, static_cast<float>(w) / 6.0f);
  }
  const cv::Scalar ink = contrasting(background);
  fitText(img, randomWord(rng, 4, 9, true), cv::Point(w / 12, h / 6), w * 5 / 6, h / 8, cv::FONT_HERSHEY_DUPLEX, ink);
  if (rng.chance(0.7)) fitText(img, randomWord(rng, 3, 10, true), cv::Point(w / 12, h / 4), w * 2 / 3, h / 14,
                               cv::FONT_HERSHEY_SIMPLEX, ink);
  paragraph(img, rng, w / 12, w * 11 / 12, h * 3 / 4, h - h / 20, std::max(5, h / 40), ink);
  cv::rectangle(img, cv::Rect(0, 0, w, h), cv::Scalar(235, 235, 235), std::max(2, w / 40));
}

void noticeBoard(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  noiseField(img, cv::Rect(0, 0, w, h), rng.seed32(), cv::Vec3f(60, 110, 170), cv::Vec3f(40, 80, 130), 3.0f);
  const int papers = rng.uniformInt(3, 7);
  for (int i = 0; i < papers; ++i) {
    const int pw = rng.uniformInt(w / 6, w / 3);
    const int ph = static_cast<int>(pw * 1.41);
    const cv::Point2f centre{static_cast<float>(rng.uniformInt(pw / 2, w - pw / 2)),
                             static_cast<float>(rng.uniformInt(ph / 2, std::max(ph / 2 + 1, h - ph / 2)))};
    const cv::RotatedRect sheet(centre, cv::Size2f(static_cast<float>(pw), static_cast<float>(ph)),
                                static_cast<float>(rng.uniform(-8, 8)));
    cv::Point2f corners[4];
    sheet.points(corners);
    std::vector<cv::Point> poly(corners, corners + 4);
    const cv::Scalar paper = rng.chance(0.7) ? cv::Scalar(245, 245, 245) : randomColour(rng, 0.2, 0.5, 0.85, 1.0);
    cv::fillConvexPoly(img, poly, paper, kLine);
    const cv::Rect box = sheet.boundingRect();
    paragraph(img, rng, box.x + pw / 6, box.x + pw * 5 / 6, box.y + ph / 8, box.y + ph * 7 / 8, std::max(4, ph / 16),
              cv::Scalar(40, 40, 40));
    cv::circle(img, cv::Point(static_cast<int>(centre.x), box.y + ph / 12), std::max(2, w / 80), randomColour(rng, 0.7, 1.0, 0.6, 1.0),
               cv::FILLED, kLine);
  }
  cv::rectangle(img, cv::Rect(0, 0, w, h), cv::Scalar(40, 70, 100), std::max(3, w / 30));
}

void door(cv::Mat& img, Rng& rng, const DecalSpec& spec, float tpm) {
  const int w = img.cols;
  const int h = img.rows;
  const int frame = std::max(3, static_cast<int>(0.05f * tpm));
  cv::Vec3f leaf = spec.colour;
  if (leaf == cv::Vec3f(0, 0, 0)) {
    leaf = rng.chance(0.5) ? randomHsv(rng, 18, 38, 0.55, 0.55, 0.4, 0.75) : randomHsv(rng, 0, 360, 0.1, 0.6, 0.4, 0.85);
  }
  img.setTo(scalar(leaf * 0.6f));
  const cv::Rect leafRect(frame, frame, w - 2 * frame, h - frame);
  noiseField(img, leafRect, rng.seed32(), leaf * 1.05f, leaf * 0.9f, std::max(4.0f, tpm * 0.05f));
  if (rng.chance(0.4)) {  // vision panel
    const cv::Rect glass(w / 2 - w / 10, h / 6, w / 5, h / 3);
    noiseField(img, glass, rng.seed32(), cv::Vec3f(90, 80, 70), cv::Vec3f(50, 45, 40), 6.0f);
    cv::rectangle(img, glass, scalar(leaf * 0.5f), std::max(2, frame / 2));
  }
  const bool handleRight = rng.chance(0.5);
  const int hx = handleRight ? w - frame - static_cast<int>(0.1f * tpm) : frame + static_cast<int>(0.06f * tpm);
  const int hy = h - static_cast<int>(1.0f * tpm);
  cv::circle(img, cv::Point(hx + static_cast<int>(0.02f * tpm), hy), std::max(3, static_cast<int>(0.03f * tpm)), cv::Scalar(190, 190, 195), cv::FILLED, kLine);
  cv::rectangle(img, cv::Rect(handleRight ? hx - static_cast<int>(0.1f * tpm) : hx, hy - static_cast<int>(0.01f * tpm),
                              static_cast<int>(0.12f * tpm), std::max(2, static_cast<int>(0.02f * tpm))),
                cv::Scalar(200, 200, 205), cv::FILLED, kLine);
  cv::rectangle(img, cv::Rect(frame, h - static_cast<int>(0.25f * tpm), w - 2 * frame, static_cast<int>(0.25f * tpm)),
                cv::Scalar(170, 170, 175), cv::FILLED, kLine);  // kick plate
  const std::string label = spec.label.empty() ? std::to_string(rng.uniformInt(100, 399)) : spec.label;
  const cv::Rect plate(w / 2 - static_cast<int>(0.1f * tpm), h - static_cast<int>(1.6f * tpm), static_cast<int>(0.2f * tpm),
                       static_cast<int>(0.08f * tpm));
  cv::rectangle(img, plate, cv::Scalar(235, 235, 235), cv::FILLED, kLine);
  fitText(img, label, cv::Point(plate.x + plate.width / 10, plate.y + plate.height * 4 / 5), plate.width * 4 / 5,
          plate.height * 3 / 5, cv::FONT_HERSHEY_SIMPLEX, cv::Scalar(30, 30, 30));
}

void window(cv::Mat& img, Rng& rng, float tpm) {
  const int w = img.cols;
  const int h = img.rows;
  // The outside: sky, a far skyline and trees, as a flat picture behind the glass.
  for (int y = 0; y < h; ++y) {
    const float f = static_cast<float>(y) / h;
    img.row(y).setTo(scalar(mixColour(cv::Vec3f(235, 190, 150), cv::Vec3f(250, 240, 230), f)));
  }
  const uint32_t cloudSeed = rng.seed32();
  for (int y = 0; y < h / 2; ++y) {
    cv::Vec3b* row = img.ptr<cv::Vec3b>(y);
    for (int x = 0; x < w; ++x) {
      const float c = fbm(x / (tpm * 0.3f), y / (tpm * 0.15f), 4, 1 << 20, 1 << 20, cloudSeed);
      if (c > 0.55f) row[x] = toBgr8(mixColour(cv::Vec3f(row[x][0], row[x][1], row[x][2]), cv::Vec3f(250, 250, 250), (c - 0.55f) * 3.0f));
    }
  }
  int x = 0;
  while (x < w) {
    const int bw = rng.uniformInt(w / 8, w / 3);
    const int top = h / 3 + rng.uniformInt(0, h / 4);
    const cv::Scalar wall = randomColour(rng, 0.0, 0.3, 0.4, 0.8);
    cv::rectangle(img, cv::Rect(x, top, bw, h - top), wall, cv::FILLED);
    for (int wy = top + 6; wy < h - 6; wy += 12) {
      for (int wx = x + 4; wx < x + bw - 6; wx += 10) {
        cv::rectangle(img, cv::Rect(wx, wy, 5, 6), cv::Scalar(110, 90, 80), cv::FILLED);
      }
    }
    x += bw + rng.uniformInt(2, std::max(2, w / 10));  // a narrow window (coarse texels) still has gaps
  }
  const int count1 = rng.uniformInt(2, 6);  // drawn once, not per iteration
  for (int i = 0; i < count1; ++i) {
    const cv::Point c{rng.uniformInt(0, w), h - rng.uniformInt(h / 10, h / 4)};
    const cv::Scalar leaves = scalar(randomHsv(rng, 90, 130, 0.6, 0.6, 0.25, 0.5));
    cv::circle(img, c, rng.uniformInt(w / 12, w / 5), leaves, cv::FILLED, kLine);
  }
  // Frame and mullions.
  const cv::Scalar frame(230, 230, 230);
  const int t = std::max(3, static_cast<int>(0.05f * tpm));
  cv::rectangle(img, cv::Rect(0, 0, w, h), frame, t * 2);
  const int panes = rng.uniformInt(2, 3);
  for (int i = 1; i < panes; ++i) cv::line(img, cv::Point(w * i / panes, 0), cv::Point(w * i / panes, h), frame, t);
  if (rng.chance(0.6)) cv::line(img, cv::Point(0, h / 3), cv::Point(w, h / 3), frame, t);
}

void painting(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  if (rng.chance(0.5)) {  // abstract
    const uint32_t seed = rng.seed32();
    const cv::Vec3f light = randomHsv(rng, 0, 360, 0.7, 0.7, 0.9, 0.9);
    const cv::Vec3f dark = randomHsv(rng, 0, 360, 0.8, 0.8, 0.3, 0.3);
    noiseField(img, cv::Rect(0, 0, w, h), seed, light, dark, static_cast<float>(w) / 5.0f);
    const int count2 = rng.uniformInt(1, 4);  // drawn once, not per iteration
    for (int i = 0; i < count2; ++i) {
      const cv::Point centre{rng.uniformInt(0, w), rng.uniformInt(0, h)};
      const int radius = rng.uniformInt(w / 12, w / 4);
      cv::circle(img, centre, radius, randomColour(rng), cv::FILLED, kLine);
    }
  } else {  // landscape: sky, sun, hills
    const cv::Scalar sky = randomColour(rng, 0.2, 0.6, 0.7, 1.0);
    img.setTo(sky);
    cv::circle(img, cv::Point(rng.uniformInt(w / 5, w * 4 / 5), h / 4), std::max(3, w / 12), cv::Scalar(120, 220, 250),
               cv::FILLED, kLine);
    for (int layer = 0; layer < 3; ++layer) {
      std::vector<cv::Point> hill;
      const double phase = rng.uniform(0, 6.28);
      const double freq = rng.uniform(1.0, 3.0);
      const int base = h / 2 + layer * h / 8;
      for (int x = 0; x <= w; x += std::max(1, w / 40)) {
        hill.emplace_back(x, base - static_cast<int>(h / 10.0 * std::sin(phase + freq * 6.28 * x / w)));
      }
      hill.emplace_back(w, h);
      hill.emplace_back(0, h);
      cv::fillPoly(img, std::vector<std::vector<cv::Point>>{hill},
                   scalar(hsv(static_cast<float>(rng.uniform(80, 150)), 0.5f, 0.55f - 0.12f * layer)), kLine);
    }
  }
  const int t = std::max(3, w / 14);
  cv::rectangle(img, cv::Rect(0, 0, w, h), rng.chance(0.5) ? cv::Scalar(40, 150, 200) : cv::Scalar(30, 30, 30), t);
}

void whiteboard(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  img.setTo(cv::Scalar(246, 246, 244));
  const std::vector<cv::Scalar> markers = {cv::Scalar(160, 40, 20), cv::Scalar(20, 20, 20), cv::Scalar(30, 30, 190),
                                           cv::Scalar(40, 140, 30)};
  const int count3 = rng.uniformInt(2, 4);  // drawn once, not per iteration
  for (int i = 0; i < count3; ++i) {
    const cv::Scalar ink = rng.pick(markers);
    const int x0 = rng.uniformInt(w / 20, w / 2);
    const int y0 = rng.uniformInt(h / 10, h * 2 / 3);
    paragraph(img, rng, x0, std::min(w - w / 20, x0 + w / 3), y0, std::min(h - h / 10, y0 + h / 4), std::max(6, h / 18), ink);
  }
  const int count4 = rng.uniformInt(2, 5);  // drawn once, not per iteration
  for (int i = 0; i < count4; ++i) {
    const cv::Scalar ink = rng.pick(markers);
    const cv::Point a{rng.uniformInt(0, w), rng.uniformInt(0, h)};
    const cv::Point b{rng.uniformInt(0, w), rng.uniformInt(0, h)};
    switch (rng.uniformInt(0, 2)) {
      case 0: cv::arrowedLine(img, a, b, ink, 2, kLine, 0, 0.08); break;
      case 1: cv::circle(img, a, rng.uniformInt(h / 12, h / 5), ink, 2, kLine); break;
      default: cv::rectangle(img, cv::Rect(a, b), ink, 2, kLine);
    }
  }
  cv::rectangle(img, cv::Rect(0, 0, w, h), cv::Scalar(190, 190, 195), std::max(3, h / 40));
}

void sign(cv::Mat& img, Rng& rng, const DecalSpec& spec) {
  const int w = img.cols;
  const int h = img.rows;
  const cv::Scalar plate = randomColour(rng, 0.3, 0.8, 0.25, 0.6);
  img.setTo(plate);
  const std::string label = spec.label.empty() ? std::to_string(rng.uniformInt(100, 399)) : spec.label;
  fitText(img, label, cv::Point(w / 10, h / 2), w * 4 / 5, h * 2 / 5, cv::FONT_HERSHEY_DUPLEX, cv::Scalar(250, 250, 250));
  fitText(img, randomWord(rng, 5, 11, true), cv::Point(w / 10, h * 5 / 6), w * 4 / 5, h / 5, cv::FONT_HERSHEY_SIMPLEX,
          cv::Scalar(230, 230, 230));
  cv::rectangle(img, cv::Rect(0, 0, w, h), cv::Scalar(220, 220, 220), std::max(1, h / 20));
}

void panel(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  const int kind = rng.uniformInt(0, 2);
  if (kind == 0) {  // electrical panel
    img.setTo(cv::Scalar(190, 195, 195));
    cv::rectangle(img, cv::Rect(w / 10, h / 10, w * 4 / 5, h * 4 / 5), cv::Scalar(150, 155, 155), 2, kLine);
    cv::rectangle(img, cv::Rect(w / 3, h / 20, w / 3, h / 12), cv::Scalar(20, 200, 240), cv::FILLED);
    fitText(img, "!", cv::Point(w / 2 - w / 30, h / 20 + h / 14), w / 15, h / 14, cv::FONT_HERSHEY_SIMPLEX, cv::Scalar(0, 0, 0));
    cv::circle(img, cv::Point(w * 4 / 5, h / 2), std::max(2, w / 25), cv::Scalar(60, 60, 60), cv::FILLED, kLine);
  } else if (kind == 1) {  // fire extinguisher cabinet
    img.setTo(cv::Scalar(30, 30, 190));
    cv::rectangle(img, cv::Rect(w / 8, h / 8, w * 3 / 4, h * 3 / 4), cv::Scalar(200, 210, 215), cv::FILLED);
    cv::rectangle(img, cv::Rect(w * 3 / 8, h / 4, w / 4, h / 2), cv::Scalar(20, 20, 170), cv::FILLED, kLine);
    fitText(img, "FIRE", cv::Point(w / 6, h * 15 / 16), w * 2 / 3, h / 10, cv::FONT_HERSHEY_DUPLEX, cv::Scalar(250, 250, 250));
  } else {  // switch plate with a label
    img.setTo(cv::Scalar(236, 238, 238));
    cv::rectangle(img, cv::Rect(w / 3, h / 4, w / 3, h / 2), cv::Scalar(210, 212, 212), cv::FILLED, kLine);
    cv::rectangle(img, cv::Rect(0, 0, w, h), cv::Scalar(180, 180, 180), 1, kLine);
  }
  paragraph(img, rng, w / 10, w * 9 / 10, h * 7 / 10, h * 19 / 20, std::max(3, h / 20), cv::Scalar(30, 30, 30));
}

void clock(cv::Mat& img, Rng& rng) {
  const int w = img.cols;
  const int h = img.rows;
  const cv::Point c(w / 2, h / 2);
  const int r = std::min(w, h) / 2 - 1;
  img.setTo(cv::Scalar(200, 200, 200));
  cv::circle(img, c, r, cv::Scalar(30, 30, 30), cv::FILLED, kLine);
  cv::circle(img, c, r * 9 / 10, cv::Scalar(245, 245, 245), cv::FILLED, kLine);
  for (int i = 0; i < 12; ++i) {
    const double a = i * M_PI / 6.0;
    cv::line(img, c + cv::Point(static_cast<int>(0.75 * r * std::cos(a)), static_cast<int>(0.75 * r * std::sin(a))),
             c + cv::Point(static_cast<int>(0.85 * r * std::cos(a)), static_cast<int>(0.85 * r * std::sin(a))),
             cv::Scalar(20, 20, 20), std::max(1, r / 20), kLine);
  }
  const double hour = rng.uniform(0, 2 * M_PI);
  const double minute = rng.uniform(0, 2 * M_PI);
  cv::line(img, c, c + cv::Point(static_cast<int>(0.45 * r * std::sin(hour)), static_cast<int>(-0.45 * r * std::cos(hour))),
           cv::Scalar(10, 10, 10), std::max(2, r / 10), kLine);
  cv::line(img, c, c + cv::Point(static_cast<int>(0.7 * r * std::sin(minute)), static_cast<int>(-0.7 * r * std::cos(minute))),
           cv::Scalar(10, 10, 10), std::max(1, r / 16), kLine);
}

}  // namespace

const char* decalName(DecalKind kind) {
  switch (kind) {
    case DecalKind::kPoster: return "poster";
    case DecalKind::kNoticeBoard: return "notice_board";
    case DecalKind::kDoor: return "door";
    case DecalKind::kWindow: return "window";
    case DecalKind::kPainting: return "painting";
    case DecalKind::kWhiteboard: return "whiteboard";
    case DecalKind::kSign: return "sign";
    case DecalKind::kPanel: return "panel";
    case DecalKind::kClock: return "clock";
  }
  return "unknown";
}

DecalLayout typicalDecalLayout(DecalKind kind, Rng& rng) {
  auto u = [&](double a, double b) { return static_cast<float>(rng.uniform(a, b)); };
  switch (kind) {
    case DecalKind::kPoster: {
      const float w = u(0.4, 0.8);
      return {w, w * u(1.2f, 1.45f), u(0.9, 1.2)};
    }
    case DecalKind::kNoticeBoard: return {u(0.9, 1.6), u(0.7, 1.0), u(0.9, 1.1)};
    case DecalKind::kDoor: return {u(0.85, 0.95), 2.05f, 0.0f};
    case DecalKind::kWindow: return {u(1.0, 2.0), u(1.1, 1.4), u(0.8, 1.0)};
    case DecalKind::kPainting: return {u(0.4, 1.0), u(0.35, 0.8), u(1.2, 1.4)};
    case DecalKind::kWhiteboard: return {u(1.2, 2.0), u(0.9, 1.2), u(0.85, 0.95)};
    case DecalKind::kSign: return {u(0.18, 0.3), u(0.12, 0.18), u(1.45, 1.6)};
    case DecalKind::kPanel: return {u(0.3, 0.6), u(0.4, 0.8), u(0.9, 1.3)};
    case DecalKind::kClock: {
      const float d = u(0.25, 0.4);
      return {d, d, u(1.9, 2.1)};
    }
  }
  return {0.5f, 0.5f, 1.0f};
}

std::string randomWord(Rng& rng, int minLength, int maxLength, bool upperCase) {
  static const char* kConsonants = "bcdfghklmnprstvwz";
  static const char* kVowels = "aeiou";
  const int n = rng.uniformInt(minLength, maxLength);
  std::string word;
  for (int i = 0; i < n; ++i) {
    // Alternating consonants and vowels reads like print; a digit now and then like codes.
    char c = (i % 2 == 0) ? kConsonants[rng.uniformInt(0, 16)] : kVowels[rng.uniformInt(0, 4)];
    if (rng.chance(0.04)) c = static_cast<char>('0' + rng.uniformInt(0, 9));
    if (upperCase || (i == 0 && rng.chance(0.3))) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    word += c;
  }
  return word;
}

cv::Mat generateDecalImage(const DecalSpec& spec, float tpm) {
  const int w = std::max(8, static_cast<int>(std::lround(spec.width * tpm)));
  const int h = std::max(8, static_cast<int>(std::lround(spec.height * tpm)));
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(200, 200, 200));
  Rng rng(spec.seed, decalName(spec.kind));
  switch (spec.kind) {
    case DecalKind::kPoster: poster(img, rng); break;
    case DecalKind::kNoticeBoard: noticeBoard(img, rng); break;
    case DecalKind::kDoor: door(img, rng, spec, tpm); break;
    case DecalKind::kWindow: window(img, rng, tpm); break;
    case DecalKind::kPainting: painting(img, rng); break;
    case DecalKind::kWhiteboard: whiteboard(img, rng); break;
    case DecalKind::kSign: sign(img, rng, spec); break;
    case DecalKind::kPanel: panel(img, rng); break;
    case DecalKind::kClock: clock(img, rng); break;
  }
  return img;
}

Texture makeDecalTexture(const DecalSpec& spec, float tpm) {
  return Texture(generateDecalImage(spec, tpm), false, tpm);
}

}  // namespace rtabmap::sim
