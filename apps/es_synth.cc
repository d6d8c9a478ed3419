// Generates a synthetic water scene with ground truth: frames, water masks,
// exact COLMAP poses, a held-out split, the true velocity field on a grid
// and per-frame depth. See docs/SYNTH.md.
//
//   es_synth --out DIR
//            [--preset waterfall|stream|fountain|droplets|pathtraced|planks]
//            [--frames 120] [--width 320 --height 240] [--seed N]
//            [--stochasticity S]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/flag_checks.h"
#include "core/io/output_dir.h"
#include "synth/scene.h"
#include "synth/writer.h"

constexpr char kUsage[] =
    "Generates a synthetic water scene with ground truth.\n"
    "  es_synth --out DIR "
    "[--preset waterfall|stream|fountain|droplets|pathtraced|planks]\n"
    "           [--frames 120]\n"
    "           [--width 320 --height 240] [--seed N] [--stochasticity S]";

DEFINE_string(out, "", "Output scene directory (created).");
DEFINE_string(preset, "waterfall", "Scene: waterfall, stream, fountain, "
              "droplets (a spray of small faint droplets), pathtraced (that "
              "spray filmed as a path tracer renders it: glints, motion "
              "blur, sample noise) or planks (pathtraced in front of walls "
              "of fine vertical boards: a trap for automatic masks).");
DEFINE_int32(frames, 120, "Number of frames.");
DEFINE_int32(width, 320, "Image width in pixels.");
DEFINE_int32(height, 240, "Image height in pixels.");
DEFINE_uint64(seed, 1, "Random seed; the same seed gives the same bytes.");
DEFINE_uint64(water_seed, 0, "> 0: seeds only the water's particles, so "
              "the scene keeps its scenery, cameras, flow and split and "
              "shows another realization of the same stochastic water (an "
              "oracle to calibrate PSNR and realism: es_compare); 0: "
              "derived from --seed.");
DEFINE_double(stochasticity, 1.0,
              "Per-particle random perturbation of the flow (0: every "
              "particle follows the analytic field exactly).");
DEFINE_double(detail, 1.0,
              "Scales the number of Gaussians (scenery and water); < 1 for "
              "quick, coarse scenes.");
DEFINE_int32(substeps, 4, "RK4 integration steps per frame.");
DEFINE_int32(grid_resolution, 32,
             "Ground-truth velocity grid nodes along the water box's longest "
             "side.");
DEFINE_int32(num_points, 4000, "Points in sparse/0/points3D.txt.");

int main(int argc, char** argv) {
  return es::RunApp(argc, argv, kUsage, [] {
    es::RequireFlag("out", FLAGS_out);
    // Stage 1 seeds its Gaussians from these points: none is useless.
    es::RequireAtLeast("num_points", FLAGS_num_points, 1);
    es::SynthSettings s;
    s.preset = FLAGS_preset;
    s.frames = FLAGS_frames;
    s.width = FLAGS_width;
    s.height = FLAGS_height;
    s.seed = FLAGS_seed;
    s.water_seed = FLAGS_water_seed;
    s.stochasticity = FLAGS_stochasticity;
    s.detail = FLAGS_detail;
    s.substeps = FLAGS_substeps;
    s.grid_resolution = FLAGS_grid_resolution;
    s.num_points = FLAGS_num_points;
    // Before generating: a scene takes seconds to minutes to make.
    es::PrepareOutputDirectory(FLAGS_out, "out");
    const auto start = std::chrono::steady_clock::now();
    const es::SynthScene scene = es::GenerateSynthScene(s);
    es::WriteSynthScene(scene, FLAGS_out);
    const double seconds = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
    const std::vector<double>& c = scene.coverage;
    const double mean =
        std::accumulate(c.begin(), c.end(), 0.0) / c.size();
    std::printf(
        "%s: %s, %d frames %dx%d, %d scenery + ~%d water Gaussians, "
        "%zu points3D\n",
        FLAGS_out.c_str(), s.preset.c_str(), s.frames, s.width, s.height,
        scene.scenery.size(), scene.num_water.back(),
        scene.sparse.points.size());
    std::printf("water coverage: mean %.1f%%, min %.1f%%, max %.1f%%\n",
                100 * mean, 100 * *std::min_element(c.begin(), c.end()),
                100 * *std::max_element(c.begin(), c.end()));
    std::printf("done in %.1f s\n", seconds);
    return 0;
  });
}
