// Decals: room signs beside doors, posters, notice boards, paintings, whiteboards, panels,
// clocks, closed doors along corridors, windows on the facade. Plain walls get (almost) none:
// they are the building's textureless stretches.
#include <algorithm>
#include <cmath>

#include "BuildingInternal.h"
#include "rtabmap_core/sim/Decals.h"

namespace rtabmap::sim::detail {

namespace {

struct Used {
  std::vector<std::pair<float, float>> spans;
  bool free(float s0, float s1) const {
    for (const auto& [a, b] : spans) {
      if (s0 < b + 0.15f && s1 > a - 0.15f) return false;  // keep a hand's width between pictures
    }
    return true;
  }
};

void addDecalTexture(Context& ctx, int face, DecalKind kind, float s0, float width, float bottom, float height,
                     const std::string& label, Rng& rng) {
  World& world = *ctx.building.world;
  DecalSpec spec;
  spec.kind = kind;
  spec.seed = rng.seed32();
  spec.width = width;
  spec.height = height;
  spec.label = label;
  const int texture = world.addTexture(makeDecalTexture(spec, ctx.spec.decalTexelsPerMetre));
  Decal d;
  d.texture = texture;
  d.s0 = s0;
  d.s1 = s0 + width;
  d.h0 = bottom;
  d.h1 = bottom + height;
  world.addDecal(face, d);
}

// Tries to hang one decal of that kind somewhere on the face; true if it found room.
bool hang(Context& ctx, const WallFace& wf, DecalKind kind, Used& used, Rng& rng) {
  const Face& face = ctx.building.world->faces()[static_cast<size_t>(wf.face)];
  DecalLayout layout = typicalDecalLayout(kind, rng);
  const float ceiling = static_cast<float>(ctx.spec.ceilingHeight);
  layout.height = std::min(layout.height, ceiling - 0.1f - layout.bottom);
  const float length = static_cast<float>(face.length);
  if (layout.height < 0.1f || layout.width > length - 0.5f) return false;
  for (int attempt = 0; attempt < 6; ++attempt) {
    const float s0 = static_cast<float>(rng.uniform(0.25, length - 0.25 - layout.width));
    if (!used.free(s0, s0 + layout.width)) continue;
    addDecalTexture(ctx, wf.face, kind, s0, layout.width, layout.bottom, layout.height, "", rng);
    used.spans.emplace_back(s0, s0 + layout.width);
    return true;
  }
  return false;
}

}  // namespace

void placeDecals(Context& ctx, Rng& rng) {
  const Building& b = ctx.building;
  const World& world = *b.world;
  const BuildingSpec& spec = ctx.spec;
  std::vector<Used> used(world.faces().size());

  // A sign beside every doorway, on the corridor side, with the room's number.
  if (spec.decalDensity > 0.0) {
    const double h = 0.5 * spec.wallThickness;
    for (const Door& door : b.doors) {
      const Eigen::Vector2d along(-door.inward.y(), door.inward.x());
      const Eigen::Vector2d jamb = door.centre - h * door.inward + (rng.chance(0.5) ? 0.5 : -0.5) * door.width * along;
      for (const WallFace& wf : ctx.wallFaces) {
        if (wf.area != door.corridor) continue;
        const Face& f = world.faces()[static_cast<size_t>(wf.face)];
        const bool atA = (f.a - jamb).norm() < 1e-6;
        const bool atB = (f.b - jamb).norm() < 1e-6;
        if (!atA && !atB) continue;
        DecalLayout layout = typicalDecalLayout(DecalKind::kSign, rng);
        if (f.length < layout.width + 0.2) break;
        const float s0 = atA ? 0.12f : static_cast<float>(f.length) - 0.12f - layout.width;
        const std::string& name = b.areas[static_cast<size_t>(door.room)].name;
        const std::string number = name.substr(name.find(' ') + 1);
        addDecalTexture(ctx, wf.face, DecalKind::kSign, s0, layout.width, layout.bottom, layout.height, number, rng);
        used[static_cast<size_t>(wf.face)].spans.emplace_back(s0, s0 + layout.width);
        break;
      }
    }
  }

  for (const WallFace& wf : ctx.wallFaces) {
    const Face& f = world.faces()[static_cast<size_t>(wf.face)];
    const Area& area = b.areas[static_cast<size_t>(wf.area)];
    Used& u = used[static_cast<size_t>(wf.face)];
    const bool corridor = area.kind == AreaKind::kCorridor;
    if (wf.facade && !(corridor && spec.plainCorridors)) {
      // Windows along the facade, about one per 3 m.
      const int windows = static_cast<int>(f.length / 3.0);
      for (int k = 0; k < windows; ++k) hang(ctx, wf, DecalKind::kWindow, u, rng);
    }
    double perMetre;
    std::vector<DecalKind> kinds;
    std::vector<double> weights;
    if (corridor) {
      perMetre = spec.plainCorridors ? 0.02 : 1.0 / 3.5;
      if (spec.plainCorridors) {
        kinds = {DecalKind::kDoor, DecalKind::kPanel};
        weights = {2, 1};
      } else {
        kinds = {DecalKind::kPoster, DecalKind::kNoticeBoard, DecalKind::kDoor, DecalKind::kPanel, DecalKind::kPainting, DecalKind::kClock};
        weights = {25, 20, 20, 15, 10, 3};
      }
    } else if (wf.plain) {
      perMetre = 0.05;  // a switch plate or a clock now and then: still a plain wall
      kinds = {DecalKind::kPanel, DecalKind::kClock};
      weights = {3, 1};
    } else {
      perMetre = 1.0 / 2.5;
      kinds = {DecalKind::kPoster, DecalKind::kPainting, DecalKind::kWhiteboard, DecalKind::kNoticeBoard, DecalKind::kPanel, DecalKind::kClock};
      weights = {30, 15, 10, 8, 8, 4};
    }
    const double expected = spec.decalDensity * perMetre * f.length;
    // Whole decals expected, plus one more with the fractional part's probability.
    int count = static_cast<int>(expected);
    if (rng.chance(expected - count)) ++count;
    for (int k = 0; k < count; ++k) hang(ctx, wf, kinds[static_cast<size_t>(rng.weighted(weights))], u, rng);
  }
}

}  // namespace rtabmap::sim::detail
