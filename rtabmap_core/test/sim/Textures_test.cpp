// Deterministic randomness, mip-mapped textures, procedural materials and decals.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "common/TestData.h"
#include "rtabmap_core/sim/Decals.h"
#include "rtabmap_core/sim/Materials.h"
#include "rtabmap_core/sim/PngWriter.h"
#include "rtabmap_core/sim/Random.h"
#include "rtabmap_core/sim/Texture.h"

using namespace rtabmap::sim;
using rtabmap::test::drawSeed;

TEST(SimRandom, SameSeedSameNumbersAndNamedStreamsDiffer) {
  Rng a(42), b(42), c(43), d(42, "odometry"), e(42, "imu");
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next(), b.next());
  EXPECT_NE(Rng(42).next(), c.next());
  EXPECT_NE(d.next(), e.next());
  EXPECT_EQ(Rng(42, "odometry").next(), Rng(42, "odometry").next());
}

TEST(SimRandom, DistributionsHaveTheirMoments) {
  Rng rng(drawSeed(1));
  double sum = 0, sum2 = 0, usum = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double x = rng.normal();
    sum += x;
    sum2 += x * x;
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    usum += u;
    const int k = rng.uniformInt(3, 5);
    ASSERT_GE(k, 3);
    ASSERT_LE(k, 5);
  }
  EXPECT_NEAR(sum / n, 0.0, 0.03);
  EXPECT_NEAR(sum2 / n, 1.0, 0.05);
  EXPECT_NEAR(usum / n, 0.5, 0.01);
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < 9000; ++i) ++counts[rng.weighted({1.0, 2.0, 0.0})];
  EXPECT_EQ(counts[2], 0);
  EXPECT_NEAR(counts[1] / 9000.0, 2.0 / 3.0, 0.03);
}

TEST(SimTexture, MipChainHalvesDownToOneTexel) {
  cv::Mat img(32, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  const Texture t(img, true, 16.0f);
  ASSERT_EQ(t.levels(), 7);  // 64x32, 32x16, ..., 1x1
  EXPECT_EQ(t.image(1).cols, 32);
  EXPECT_EQ(t.image(1).rows, 16);
  EXPECT_EQ(t.image(6).cols, 1);
  EXPECT_EQ(t.image(6).at<cv::Vec3b>(0, 0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(cv::norm(t.image(0), img, cv::NORM_INF), 0.0);  // stored transposed, shown as given
  EXPECT_THROW(Texture(cv::Mat(30, 64, CV_8UC3), true, 1.0f), std::invalid_argument);  // wrap needs powers of two
  EXPECT_NO_THROW(Texture(cv::Mat(30, 50, CV_8UC3, cv::Scalar(0)), false, 1.0f));
}

TEST(SimTexture, BilinearSamplingWrapsOrClamps) {
  cv::Mat img(4, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  img.col(3).setTo(cv::Scalar(200, 200, 200));
  uint8_t out[3];
  const Texture wrapped(img, true, 1.0f);
  sampleBilinear(wrapped.level(0), 0.0f, 2.0f, out);  // between texel 3 (200) and texel 0 (0), across the seam
  EXPECT_NEAR(out[0], 100, 1);
  sampleBilinear(wrapped.level(0), 3.5f, 2.0f, out);  // a texel centre: exact
  EXPECT_EQ(out[0], 200);
  const Texture clamped(img, false, 1.0f);
  sampleBilinear(clamped.level(0), 0.0f, 2.0f, out);  // clamps to texel 0
  EXPECT_EQ(out[0], 0);
  sampleBilinear(clamped.level(0), 9.0f, 2.0f, out);
  EXPECT_EQ(out[0], 200);
}

TEST(SimTexture, LevelMatchesTheFootprint) {
  const Texture t(cv::Mat(64, 64, CV_8UC3, cv::Scalar(1, 2, 3)), true, 1.0f);
  EXPECT_EQ(t.levelFor(0.2f), 0);
  EXPECT_EQ(t.levelFor(1.0f), 0);
  EXPECT_EQ(t.levelFor(1.3f), 0);
  EXPECT_EQ(t.levelFor(1.5f), 1);
  EXPECT_EQ(t.levelFor(2.0f), 1);
  EXPECT_EQ(t.levelFor(4.0f), 2);
  EXPECT_EQ(t.levelFor(5.0f), 2);
  EXPECT_EQ(t.levelFor(6.0f), 3);
  EXPECT_EQ(t.levelFor(1e6f), t.levels() - 1);
}

TEST(SimMaterials, TilesAreSeamlessAndDeterministic) {
  Rng rng(drawSeed(5));
  const MaterialKind kinds[] = {MaterialKind::kBrick, MaterialKind::kWoodPanels, MaterialKind::kWallpaper, MaterialKind::kConcrete,
                                MaterialKind::kCarpet, MaterialKind::kParquet, MaterialKind::kCeilingTiles, MaterialKind::kBookshelf,
                                MaterialKind::kMarble, MaterialKind::kFoliage};
  for (MaterialKind kind : kinds) {
    SCOPED_TRACE(materialName(kind));
    const MaterialSpec spec = randomMaterialSpec(kind, rng);
    const cv::Mat a = generateMaterialImage(spec, 128, 32.0f);
    const cv::Mat b = generateMaterialImage(spec, 128, 32.0f);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
    MaterialSpec other = spec;
    other.seed += 1;
    if (kind != MaterialKind::kCeilingTiles) {
      EXPECT_GT(cv::norm(a, generateMaterialImage(other, 128, 32.0f), cv::NORM_L1), 0.0);
    }
    // Periodic: one tile period away, the same colour (so the tile wraps without a seam).
    const float period = 128 / 32.0f;
    Rng points(drawSeed(static_cast<unsigned>(kind)));
    for (int k = 0; k < 200; ++k) {
      const float x = static_cast<float>(points.uniform(0.0, period));
      const float y = static_cast<float>(points.uniform(0.0, period));
      const cv::Vec3f c = materialColourAt(spec, x, y, 128, 32.0f);
      ASSERT_LT(cv::norm(c - materialColourAt(spec, x + period, y, 128, 32.0f)), 1.0) << x << "," << y;
      ASSERT_LT(cv::norm(c - materialColourAt(spec, x, y + period, 128, 32.0f)), 1.0) << x << "," << y;
    }
  }
}

// Tile variants (a surface shows one per tile): each is deterministic and periodic, variant 0 is
// the plain tile, another draws other details inside the same structure, and any two meet without
// a seam: across a tile border from variant a to variant b the colour jumps no more than it does
// from variant a to itself (mortar, grout and grid lines on the border jump in both).
TEST(SimMaterials, TileVariantsDifferAndMeetWithoutASeam) {
  Rng rng(drawSeed(6));
  const int size = 128;
  const float tpm = 32.0f;
  const float period = size / tpm;
  int varied = 0;
  for (int k = 0; k <= static_cast<int>(MaterialKind::kMetal); ++k) {
    const MaterialKind kind = static_cast<MaterialKind>(k);
    if (!variesPerTile(kind)) continue;
    ++varied;
    SCOPED_TRACE(materialName(kind));
    const MaterialSpec spec = randomMaterialSpec(kind, rng);
    const cv::Mat v0 = generateMaterialImage(spec, size, tpm);
    const cv::Mat v1 = generateMaterialImage(spec, size, tpm, 1);
    EXPECT_EQ(cv::norm(v0, generateMaterialImage(spec, size, tpm, 0), cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(v1, generateMaterialImage(spec, size, tpm, 1), cv::NORM_INF), 0.0);
    // Other details: a visible share of the texels moves by more than 4 grey levels.
    cv::Mat diff, grey;
    cv::absdiff(v0, v1, diff);
    cv::cvtColor(diff, grey, cv::COLOR_BGR2GRAY);
    EXPECT_GT(cv::countNonZero(grey > 4), size * size / 50);
    Rng points(drawSeed(static_cast<unsigned>(k) + 100));
    const float eps = 1e-4f;  // a three-hundredth of a texel, a fiftieth of the finest noise
    for (int i = 0; i < 300; ++i) {
      const float u = static_cast<float>(points.uniform(0.0, period));
      const int a = points.uniformInt(0, 3);
      const int b = points.uniformInt(0, 3);
      for (const bool alongX : {true, false}) {
        auto at = [&](float across, int variant) {
          return alongX ? materialColourAt(spec, across, u, size, tpm, variant)
                        : materialColourAt(spec, u, across, size, tpm, variant);
        };
        const cv::Vec3f before = at(period - eps, a);
        const double jumpSame = cv::norm(before - at(period + eps, a));
        const double jumpOther = cv::norm(before - at(period + eps, b));
        ASSERT_LE(jumpOther, jumpSame + 3.0) << "variants " << a << " -> " << b << (alongX ? " along x" : " along y")
                                             << " at " << u;
      }
      // Each variant is periodic on its own.
      const cv::Vec3f c = materialColourAt(spec, u, 0.3f * u, size, tpm, a);
      ASSERT_LT(cv::norm(c - materialColourAt(spec, u + period, 0.3f * u, size, tpm, a)), 1.0);
    }
  }
  EXPECT_GE(varied, 8);
  EXPECT_FALSE(variesPerTile(MaterialKind::kPaint));
  EXPECT_FALSE(variesPerTile(MaterialKind::kWallpaper));
  EXPECT_FALSE(variesPerTile(MaterialKind::kBookshelf));
}

// A texture with variants picks one per tile by a hash of the tile and the surface's key: the
// same every time, and not the same everywhere.
TEST(SimTexture, VariantsArePickedPerTile) {
  std::vector<cv::Mat> pictures;
  for (int v = 0; v < 4; ++v) pictures.emplace_back(8, 8, CV_8UC3, cv::Scalar(10 * v, 0, 0));
  const Texture t(pictures, true, 2.0f, 77u);
  ASSERT_EQ(t.variants(), 4);
  ASSERT_EQ(t.levels(), 4);
  EXPECT_EQ(t.image(2, 3).at<cv::Vec3b>(0, 0), cv::Vec3b(30, 0, 0));
  EXPECT_EQ(t.level(0).shiftX, 3);
  EXPECT_EQ(t.level(1).shiftY, 2);
  EXPECT_THROW(t.image(0, 4), std::out_of_range);
  EXPECT_THROW(Texture(pictures, false, 1.0f), std::invalid_argument);  // a decal has no tiles
  int counts[4] = {0, 0, 0, 0};
  int keyChanges = 0;
  for (int ty = -10; ty < 10; ++ty) {
    for (int tx = -10; tx < 10; ++tx) {
      const int v = t.variantAt(5u, tx, ty);
      ASSERT_EQ(v, t.variantAt(5u, tx, ty));
      ++counts[v];
      keyChanges += v != t.variantAt(6u, tx, ty);
      // levelAt: texel coordinates in tile (tx, ty) give that tile's variant, at every level.
      uint8_t bgr[3];
      const float s = tx * 8.0f + 4.0f;
      const float u = ty * 8.0f + 4.0f;
      sampleBilinear(t.levelAt(1, 5u, s, u), s, u, bgr);
      ASSERT_EQ(bgr[0], 10 * v);
    }
  }
  for (int v = 0; v < 4; ++v) EXPECT_GT(counts[v], 60) << v;  // about 100 each
  EXPECT_GT(keyChanges, 200);
  const Texture single(pictures.front(), true, 2.0f);
  EXPECT_EQ(single.variants(), 1);
  EXPECT_EQ(single.variantAt(5u, 3, 4), 0);
}

// Corners a detector finds on a material, with an absolute threshold (FAST, 20 grey levels):
// textured materials are rich, paint, plaster and linoleum nearly empty.
TEST(SimMaterials, TexturedAreFeatureRichAndPlainAreNot) {
  Rng rng(drawSeed(11));
  auto corners = [&](MaterialKind kind) {
    const cv::Mat img = generateMaterialImage(randomMaterialSpec(kind, rng), 512, 128.0f);  // the real density
    cv::Mat grey;
    cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> kps;
    cv::FAST(grey, kps, 20, true);
    return kps.size();
  };
  for (MaterialKind plain : {MaterialKind::kPaint, MaterialKind::kPlaster, MaterialKind::kLinoleum}) {
    EXPECT_LT(corners(plain), 40u) << materialName(plain);
    EXPECT_TRUE(isTextureless(plain));
  }
  for (MaterialKind rich : {MaterialKind::kBrick, MaterialKind::kBookshelf, MaterialKind::kWallpaper, MaterialKind::kConcrete,
                            MaterialKind::kCabinet, MaterialKind::kFoliage}) {
    EXPECT_GT(corners(rich), 150u) << materialName(rich);
    EXPECT_FALSE(isTextureless(rich));
  }
}

TEST(SimDecals, EachSeedDrawsAnotherPictureOfTheAskedSize) {
  DecalSpec spec;
  spec.kind = DecalKind::kPoster;
  spec.width = 0.5f;
  spec.height = 0.7f;
  // Seeds 1 and 2 on every test draw: what a seed gives (the same picture again, another for
  // another seed) is the subject.
  spec.seed = 1;
  const cv::Mat a = generateDecalImage(spec, 100.0f);
  EXPECT_EQ(a.cols, 50);
  EXPECT_EQ(a.rows, 70);
  EXPECT_EQ(cv::norm(a, generateDecalImage(spec, 100.0f), cv::NORM_INF), 0.0);
  spec.seed = 2;
  EXPECT_GT(cv::norm(a, generateDecalImage(spec, 100.0f), cv::NORM_L1), 1000.0);
  // Every kind draws something with detail (not a flat plate).
  Rng rng(drawSeed(3));
  for (DecalKind kind : {DecalKind::kPoster, DecalKind::kNoticeBoard, DecalKind::kDoor, DecalKind::kWindow, DecalKind::kPainting,
                         DecalKind::kWhiteboard, DecalKind::kSign, DecalKind::kPanel, DecalKind::kClock}) {
    const DecalLayout layout = typicalDecalLayout(kind, rng);
    DecalSpec s;
    s.kind = kind;
    s.seed = drawSeed(9);
    s.width = layout.width;
    s.height = layout.height;
    const cv::Mat img = generateDecalImage(s, 200.0f);
    cv::Scalar mean, stddev;
    cv::meanStdDev(img, mean, stddev);
    EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 15.0) << decalName(kind);
  }
  EXPECT_EQ(randomWord(rng, 4, 4).size(), 4u);
}

TEST(SimDecals, EveryKindDrawsAtTheCoarsestDensityTheSimulatorAccepts) {
  // rtabmap-sim --texture-size 32 draws decals at 16 texels per metre: a 0.5 m picture is 8
  // pixels wide, and its random sizes and gaps (fractions of the width) must stay valid ranges.
  Rng rng(drawSeed(5));
  for (DecalKind kind : {DecalKind::kPoster, DecalKind::kNoticeBoard, DecalKind::kDoor, DecalKind::kWindow, DecalKind::kPainting,
                         DecalKind::kWhiteboard, DecalKind::kSign, DecalKind::kPanel, DecalKind::kClock}) {
    for (int i = 0; i < 30; ++i) {
      const DecalLayout layout = typicalDecalLayout(kind, rng);
      DecalSpec s;
      s.kind = kind;
      s.seed = static_cast<uint32_t>(rng.uniformInt(0, 1 << 30));
      s.width = layout.width;
      s.height = layout.height;
      cv::Mat img;
      ASSERT_NO_THROW(img = generateDecalImage(s, 16.0f)) << decalName(kind) << " seed " << s.seed;
      EXPECT_FALSE(img.empty()) << decalName(kind);
    }
  }
}

TEST(SimPng, EncodesLosslesslyForAnyPngReader) {
  // Pixels from the test's draw (cv::randu would draw from cv::theRNG(), whose state depends on
  // the tests run before this one).
  cv::RNG rng(drawSeed(4));
  cv::Mat colour(37, 53, CV_8UC3), grey(20, 31, CV_8UC1), depth(25, 40, CV_16UC1);
  rng.fill(colour, cv::RNG::UNIFORM, 0, 256);
  rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
  rng.fill(depth, cv::RNG::UNIFORM, 0, 65536);
  colour(cv::Rect(0, 0, 20, 20)).setTo(cv::Scalar(10, 200, 30));  // runs, for both filters
  for (const cv::Mat& m : {colour, grey, depth}) {
    const std::vector<uint8_t> png = encodePng(m);
    const cv::Mat back = cv::imdecode(png, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), m.type());
    EXPECT_EQ(cv::norm(back, m, cv::NORM_INF), 0.0);
    EXPECT_TRUE(png == encodePng(m));
  }
  EXPECT_THROW(encodePng(cv::Mat(4, 4, CV_32FC1)), std::invalid_argument);
}
