#pragma once
// Decals: the unique pictures on the walls of the simulated building (posters, notice boards,
// closed doors, windows, paintings, whiteboards, room signs, wall panels, clocks). Each is drawn
// once from its own seed, so no two are alike: they are what makes one room recognisable from
// another, as the posters and signs of a real building are. Printed text is random words in
// OpenCV's Hershey fonts (text-like strokes, not a language).
//
// Pictures are clamped textures at 256 texels per metre by default; row 0 is the top edge.
#include <opencv2/core/mat.hpp>
#include <opencv2/core/matx.hpp>

#include <cstdint>
#include <string>

#include "rtabmap_core/sim/Texture.h"

namespace rtabmap::sim {

class Rng;

enum class DecalKind {
  kPoster,
  kNoticeBoard,
  kDoor,        // a closed door (frame, leaf, handle, number plate)
  kWindow,      // a window onto a (painted) outside view
  kPainting,
  kWhiteboard,
  kSign,        // a small plate with a room number
  kPanel,       // electrical panel, fire-extinguisher cabinet, switch plate
  kClock,
};
const char* decalName(DecalKind kind);

struct DecalSpec {
  DecalKind kind = DecalKind::kPoster;
  uint32_t seed = 0;
  float width = 0.6f;   // metres
  float height = 0.8f;  // metres
  std::string label;    // room number on doors and signs ("" = made up from the seed)
  cv::Vec3f colour{0.0f, 0.0f, 0.0f};  // door leaf colour (BGR; all 0 = chosen from the seed)
};

// Where a decal of that kind usually hangs: its size and the height of its bottom edge.
struct DecalLayout {
  float width;
  float height;
  float bottom;
};
DecalLayout typicalDecalLayout(DecalKind kind, Rng& rng);

cv::Mat generateDecalImage(const DecalSpec& spec, float texelsPerMetre = 256.0f);
Texture makeDecalTexture(const DecalSpec& spec, float texelsPerMetre = 256.0f);

// A made-up word of [minLength, maxLength] letters (capitalised or not), for printed text.
std::string randomWord(Rng& rng, int minLength, int maxLength, bool upperCase = false);

}  // namespace rtabmap::sim
