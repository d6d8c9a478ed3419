#include "synth/preset.h"

#include <cmath>

#include <glog/logging.h>

#include "core/base/input_error.h"
#include "synth/random.h"

namespace es {
namespace {

using Eigen::Vector3d;

// Full-detail Gaussian spacing on the scenery (world units).
constexpr double kScenerySpacing = 0.05;

SceneryMaterial Rock() {
  return {{0.52, 0.50, 0.46}, {0.30, 0.27, 0.24}, 1.8, 0.14};
}
SceneryMaterial MossyRock() {
  return {{0.48, 0.47, 0.40}, {0.22, 0.30, 0.16}, 1.6, 0.14};
}
SceneryMaterial Cliff() {
  return {{0.50, 0.44, 0.38}, {0.26, 0.24, 0.22}, 1.1, 0.12};
}
SceneryMaterial Ground() {
  return {{0.45, 0.38, 0.28}, {0.24, 0.30, 0.17}, 1.3, 0.15};
}
SceneryMaterial Hedge() {
  return {{0.20, 0.34, 0.16}, {0.10, 0.18, 0.10}, 2.0, 0.18};
}

SceneryMaterial Boards() {
  SceneryMaterial m{{0.66, 0.52, 0.36}, {0.48, 0.34, 0.22}, 0.8, 0.10};
  m.board_width = 0.15;
  return m;
}

SceneryPlane Plane(const Vector3d& origin, const Vector3d& u,
                   const Vector3d& v, double bump,
                   const SceneryMaterial& material) {
  return {origin, u, v, bump, material};
}

// `count` half-buried rocks with centers uniform in [lo, hi] (x, z).
void ScatterRocks(int count, const Eigen::Vector2d& lo,
                  const Eigen::Vector2d& hi, double min_radius,
                  double max_radius, double ground_y, SynthRandom* r,
                  std::vector<SceneryRock>* rocks) {
  for (int i = 0; i < count; ++i) {
    SceneryRock rock;
    const double radius = r->Uniform(min_radius, max_radius);
    rock.radii = Vector3d(radius * r->Uniform(0.8, 1.3),
                          radius * r->Uniform(0.5, 0.8),
                          radius * r->Uniform(0.8, 1.3));
    rock.center = Vector3d(r->Uniform(lo.x(), hi.x()),
                           ground_y + 0.25 * rock.radii.y(),
                           r->Uniform(lo.y(), hi.y()));
    rock.roughness = r->Uniform(0.15, 0.3);
    rock.material = r->Uniform() < 0.5 ? Rock() : MossyRock();
    rocks->push_back(rock);
  }
}

// A cliff with a pool below, rocks on both sides and the camera facing it
// (the waterfall and droplet presets).
void CliffScenery(SynthRandom* r, SynthPreset* p) {
  std::vector<SceneryPlane>& planes = p->scenery.planes;
  // Cliff face, a higher wall behind its top, the valley floor. The camera
  // stays below the top, so the ledge between the walls is never seen.
  planes.push_back(Plane({-5, -0.2, -0.15}, {10, 0, 0}, {0, 3.2, 0}, 0.1,
                         Cliff()));
  planes.push_back(Plane({-7, 2.9, -2.65}, {14, 0, 0}, {0, 2.6, 0}, 0.1,
                         Cliff()));
  planes.push_back(Plane({-5, 0, -0.15}, {0, 0, 5.2}, {10, 0, 0}, 0.04,
                         Ground()));
  std::vector<SceneryRock>& rocks = p->scenery.rocks;
  ScatterRocks(6, {-3.2, 0.0}, {-1.8, 3.0}, 0.25, 0.6, 0.0, r, &rocks);
  ScatterRocks(6, {1.8, 0.0}, {3.2, 3.0}, 0.25, 0.6, 0.0, r, &rocks);
  ScatterRocks(4, {-2.5, 3.0}, {2.5, 4.0}, 0.1, 0.25, 0.0, r, &rocks);

  p->camera.start = {-1.0, 1.9, 5.8};
  p->camera.end = {1.0, 2.2, 5.5};
  p->camera.target = {0.0, 1.5, 0.8};
}

// What Waterfall and Droplets share: water falling from the lip of the
// cliff (CliffScenery) at y = 3 into a pool at y = 0.1 that drifts toward
// the camera. `flow` says how fast and wide the water leaves the lip and
// where the pool spreads.
void CliffWaterfall(WaterfallFlow flow, SynthRandom* r, SynthPreset* p) {
  flow.lip_y = 3.0;
  flow.initial_fall_speed = 0.02;
  flow.blend_y = 0.35;
  flow.blend_width = 0.12;
  flow.pool.surface_y = 0.1;
  flow.pool.relax = 0.25;
  flow.pool.drift = {0.0, 0.0, 0.012};
  p->flow = SynthFlow(flow);
  p->water.region = {Vector3d(-4, -0.3, -0.2), Vector3d(4, 3.3, 4.5)};
  p->warmup_frames = 130;
  CliffScenery(r, p);
}

void Waterfall(SynthRandom* r, SynthPreset* p) {
  p->water.num_particles = 28000;
  p->water.min_lifetime = 60;
  p->water.max_lifetime = 110;
  p->water.source = {Vector3d(-0.9, 2.98, 0.02), Vector3d(0.9, 3.05, 0.15)};
  p->look.size = 0.035;
  p->look.deep_color = {0.22, 0.38, 0.46};

  WaterfallFlow flow;
  flow.exit_speed = 0.03;
  flow.fan_out = 0.006;
  flow.pool.center = {0.0, 0.75};
  flow.pool.spread_speed = 0.035;
  flow.pool.radius = 0.9;
  CliffWaterfall(flow, r, p);
}

void Stream(SynthRandom* r, SynthPreset* p) {
  StreamFlow flow;
  flow.speed = 0.07;
  flow.half_width = 1.2;
  flow.surface_y = 0.1;
  flow.slope = 0.02;
  p->flow = SynthFlow(flow);

  p->water.num_particles = 30000;
  p->water.min_lifetime = 150;
  p->water.max_lifetime = 220;
  p->water.source = {Vector3d(-5.2, 0.17, -1.1), Vector3d(-4.8, 0.23, 1.1)};
  p->water.region = {Vector3d(-5.5, -0.3, -2.5), Vector3d(5.0, 0.8, 2.5)};
  p->look.size = 0.04;
  p->look.deep_color = {0.18, 0.32, 0.38};
  p->look.foam_speed = 0.25;
  p->warmup_frames = 240;

  // Bed sloping with the water, banks rising on both sides, a hedge behind.
  const double drop = flow.slope * 12.0;
  std::vector<SceneryPlane>& planes = p->scenery.planes;
  planes.push_back(Plane({-6, flow.slope * 6.0, -2.0}, {0, 0, 4.0},
                         {12, -drop, 0}, 0.03, Ground()));
  planes.push_back(Plane({-6, 0.5, -4.5}, {0, -0.6, 2.7}, {12, 0, 0}, 0.06,
                         Ground()));
  planes.push_back(Plane({-6, -0.1, 1.8}, {0, 0.5, 3.0}, {12, 0, 0}, 0.06,
                         Ground()));
  planes.push_back(Plane({-10, 0.3, -4.5}, {20, 0, 0}, {0, 2.5, 0}, 0.15,
                         Hedge()));
  std::vector<SceneryRock>& rocks = p->scenery.rocks;
  ScatterRocks(10, {-5.0, -2.8}, {5.0, -1.4}, 0.2, 0.55, 0.25, r, &rocks);
  ScatterRocks(8, {-4.0, 1.5}, {4.0, 2.5}, 0.15, 0.4, 0.2, r, &rocks);

  p->camera.start = {-1.3, 1.5, 3.1};
  p->camera.end = {1.1, 1.7, 2.9};
  p->camera.target = {0.0, 0.1, -0.1};
}

void Fountain(SynthRandom* r, SynthPreset* p) {
  FountainFlow flow;
  flow.nozzle = {0.0, 0.3, 0.0};
  flow.jet_speed = 0.16;
  flow.jet_height = 2.0;
  flow.core_radius = 0.22;
  flow.umbrella_speed = 0.045;
  flow.blend_y = 0.5;
  flow.blend_width = 0.1;
  flow.pool.surface_y = 0.3;
  flow.pool.relax = 0.25;
  flow.pool.center = {0.0, 0.0};
  flow.pool.spread_speed = 0.02;
  flow.pool.radius = 1.0;
  p->flow = SynthFlow(flow);

  p->water.num_particles = 24000;
  p->water.min_lifetime = 70;
  p->water.max_lifetime = 110;
  p->water.source = {Vector3d(-0.06, 0.3, -0.06), Vector3d(0.06, 0.36, 0.06)};
  p->water.region = {Vector3d(-1.8, 0.0, -1.8), Vector3d(1.8, 3.0, 1.8)};
  p->look.size = 0.035;
  p->look.deep_color = {0.20, 0.36, 0.44};
  p->look.foam_speed = 0.15;
  p->warmup_frames = 130;

  std::vector<SceneryPlane>& planes = p->scenery.planes;
  planes.push_back(Plane({-6.5, 0, -4}, {0, 0, 7.5}, {13, 0, 0}, 0.03,
                         Ground()));
  planes.push_back(Plane({-9, -0.1, -4}, {18, 0, 0}, {0, 4.0, 0}, 0.2,
                         Hedge()));
  std::vector<SceneryRock>& rocks = p->scenery.rocks;
  // The basin rim: a ring of stones; a pedestal under the nozzle.
  const int stones = 22;
  for (int i = 0; i < stones; ++i) {
    const double a = 2.0 * M_PI * (i + r->Uniform(-0.2, 0.2)) / stones;
    SceneryRock rock;
    rock.center = {1.9 * std::cos(a), 0.1, 1.9 * std::sin(a)};
    rock.radii = {0.32, 0.3, 0.32};
    rock.roughness = 0.2;
    rock.material = Rock();
    rocks.push_back(rock);
  }
  SceneryRock pedestal;
  pedestal.center = {0.0, 0.12, 0.0};
  pedestal.radii = {0.22, 0.2, 0.22};
  pedestal.material = MossyRock();
  rocks.push_back(pedestal);
  ScatterRocks(8, {-4.5, -3.5}, {4.5, -2.4}, 0.2, 0.5, 0.0, r, &rocks);

  p->camera.start = {-1.1, 1.5, 3.5};
  p->camera.end = {1.1, 1.8, 3.3};
  p->camera.target = {0.0, 0.9, 0.0};
}

// Spray: the waterfall's ledge throws a thin, wide curtain of small,
// faint droplets that the turbulence tears apart (strong, short-lived
// perturbations), so the water is high-frequency and semi-transparent
// with the background showing through everywhere.
void Droplets(SynthRandom* r, SynthPreset* p) {
  p->water.num_particles = 16000;
  p->water.min_lifetime = 50;
  p->water.max_lifetime = 100;
  p->water.turbulence = 0.4;
  p->water.turbulence_frames = 2.0;
  p->water.source = {Vector3d(-1.2, 2.96, 0.0), Vector3d(1.2, 3.06, 0.25)};
  p->look.size = 0.014;
  p->look.streak = 0.3;
  p->look.min_opacity = 0.15;
  p->look.max_opacity = 0.6;
  p->look.foam_speed = 0.08;
  p->look.deep_color = {0.30, 0.45, 0.55};

  WaterfallFlow flow;
  flow.exit_speed = 0.035;
  flow.fan_out = 0.015;
  flow.pool.center = {0.0, 0.8};
  flow.pool.spread_speed = 0.04;
  flow.pool.radius = 1.0;
  CliffWaterfall(flow, r, p);
}

// The spray of Droplets filmed as a path tracer renders it: thousands of
// smaller droplets with the sun glinting on them, motion blur and sample
// noise. Its stochastic detail and flicker are what a per-pixel loss
// cannot predict, as in rendered or real footage.
void PathTraced(SynthRandom* r, SynthPreset* p) {
  Droplets(r, p);
  p->water.num_particles = 24000;
  p->look.size = 0.011;
  p->look.streak = 0.1;  // the shutter streaks them instead
  p->look.min_opacity = 0.2;
  p->look.max_opacity = 0.75;
  p->look.glint = 1.5;
  p->look.glint_exponent = 80.0;
  p->effects.motion_blur_samples = 4;
  p->effects.shutter = 0.5;
  p->effects.noise = 0.025;
}

// The trap for automatic masks: the path-traced spray in front of walls
// of fine vertical boards (each a few pixels wide, dark seams between).
// A short static fit renders them badly, and their misfit changes as the
// hand-held camera moves, as water's does; yet they stand still.
void Planks(SynthRandom* r, SynthPreset* p) {
  PathTraced(r, p);
  for (int wall : {0, 1}) p->scenery.planes[wall].material = Boards();
}

}  // namespace

std::vector<std::string> SynthPresetNames() {
  return {"waterfall", "stream", "fountain", "droplets", "pathtraced",
          "planks"};
}

SynthPreset MakeSynthPreset(const std::string& name, double detail,
                            uint64_t seed) {
  if (!(detail > 0.0)) {
    throw InputError("synthetic scene detail must be > 0, got " +
                     std::to_string(detail));
  }
  SynthPreset p;
  p.name = name;
  SynthRandom random(SynthRandom::Derive(seed, 77));
  if (name == "waterfall") {
    Waterfall(&random, &p);
  } else if (name == "stream") {
    Stream(&random, &p);
  } else if (name == "fountain") {
    Fountain(&random, &p);
  } else if (name == "droplets") {
    Droplets(&random, &p);
  } else if (name == "pathtraced") {
    PathTraced(&random, &p);
  } else if (name == "planks") {
    Planks(&random, &p);
  } else {
    throw InputError("unknown preset '" + name +
                     "' (expected waterfall, stream, fountain, droplets, "
                     "pathtraced or planks)");
  }
  // Fewer, larger Gaussians at low detail cover the same area.
  const double grow = 1.0 / std::sqrt(detail);
  p.scenery.spacing = kScenerySpacing * grow;
  p.look.size *= grow;
  p.water.num_particles = std::max(
      1, static_cast<int>(std::lround(p.water.num_particles * detail)));
  return p;
}

}  // namespace es
