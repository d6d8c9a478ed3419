// Stage 2: initializes the motion field V from optical flow lifted to 3D
// with the static model's depth, and pretrains it on those samples.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/common/app_main.h"
#include "apps/common/device_flag.h"
#include "apps/common/flag_checks.h"
#include "core/flow/flow_lifting.h"
#include "core/fields/field_io.h"
#include "core/base/input_error.h"
#include "core/io/json_file.h"
#include "core/flow/scene_flow_io.h"
#include "core/io/output_dir.h"
#include "core/io/ply_io.h"
#include "core/io/scene.h"
#include "core/model/dynamic_set.h"
#include "core/base/stage_profile.h"
#include "solvers/eval/motion_gt.h"
#include "solvers/train/flow_pretrain.h"
#include "solvers/train/training_history.h"

DEFINE_string(scene, "", "Scene directory (images/, sparse/0/, masks/).");
DEFINE_string(static, "",
              "Static model from Stage 1 (3DGS PLY with dynamic_logit); "
              "default <scene>/static.ply.");
DEFINE_string(out, "",
              "Output directory for motion_field.bin, scene_flow_samples.bin "
              "and flow_metrics.json; "
              "default the scene directory.");
DEFINE_double(image_scale, 1.0, "Resize frames by this factor.");
DEFINE_bool(use_test_frames, false,
            "Also lift flow between held-out frames (off: they stay unseen).");
// Optical flow and lifting.
DEFINE_string(flow, "dis",
              "Optical flow method: dis, dis_fine (dis at full resolution), "
              "dis_fast, dis_ultrafast, farneback, and with OpenCV contrib "
              "deepflow, tvl1, pcaflow.");
DEFINE_string(flow_image, "fluctuation",
              "What the flow is computed on: frame (the video frames) or "
              "fluctuation (each frame minus the static model's render of "
              "it, so the still part the water is blended with is gone).");
DEFINE_bool(white_background, false,
            "The static model was trained on white (es_static "
            "--white_background): --flow_image fluctuation subtracts its "
            "render on the same background.");
DEFINE_string(water_source, "auto",
              "Water pixels from: masks (masks/), model (the static model's "
              "rendered dynamic probability), auto (masks if present).");
DEFINE_double(water_threshold, 0.5, "Mask / probability that is water.");
DEFINE_string(second_end, "plane",
              "Where a sample's second end lies on frame i+1's ray through "
              "the flow target: plane (on the plane through the first end "
              "facing camera i: no motion along the line of sight, which 2D "
              "flow does not observe) or depth (the static model's rendered "
              "depth there; rough water depth turns into spurious motion "
              "along the ray).");
DEFINE_bool(free_line_of_sight, true,
            "With --second_end plane: the samples record camera i's line "
            "of sight, and fitting V to them (here and in es_train's "
            "scene-flow prior) leaves V's motion along it free instead of "
            "pulling it to zero. false: the samples claim no motion along "
            "it (the behaviour before, for ablations).");
DEFINE_double(line_of_sight_weight, 0.0,
              "With --free_line_of_sight: the weight the fits keep on the "
              "samples' (zero) motion along the line of sight, relative to "
              "the motion across it: 0 leaves it free, 1 is "
              "--free_line_of_sight=false.");
DEFINE_int32(stride, 2, "Lift every stride-th pixel of every stride-th row.");
DEFINE_int32(frame_gap, 1,
             "Flow between frames this many video frames apart, divided "
             "by the gap: larger displacements, but stochastic water "
             "changes between the frames and fewer matches pass the "
             "forward-backward check (on es_synth water 1 was best).");
DEFINE_string(oracle_velocity, "none",
              "Diagnosis on synthetic scenes (needs SCENE/gt/): keep where the "
              "lifted samples are, but give each the true velocity there. "
              "full: all of it, seen in every direction; seen: the truth "
              "across each sample's line of sight, that line left free (a "
              "perfect 2D flow, lifted as today); none: the optical flow. "
              "The samples written (and es_train's prior) are these.");
DEFINE_double(max_fb_px, 1.0,
              "Reject flow whose forward-backward round trip misses by more "
              "than this (px): occlusions and unreliable matches.");
DEFINE_double(max_depth_jump, 0.05,
              "Reject pixels whose 3x3 depth range exceeds this fraction of "
              "the depth at either end: occluding edges.");
DEFINE_double(min_alpha, 0.5, "Rendered alpha below this has no depth.");
DEFINE_int32(max_samples, 500000,
             "Keep at most this many samples (a random subset).");
// The field.
DEFINE_double(dynamic_threshold, 0.2,
              "sigmoid(dynamic_logit) above this marks a Gaussian as water; "
              "the field's box bounds those Gaussians.");
DEFINE_int32(triplane_res, 128, "Triplane resolution R (R x R planes).");
DEFINE_int32(triplane_channels, 12, "Triplane feature channels.");
DEFINE_string(combination, "product",
              "How plane features combine: product, sum, concat.");
DEFINE_int32(mlp_width, 64, "MLP hidden width.");
DEFINE_int32(mlp_depth, 2, "MLP hidden layers.");
DEFINE_double(velocity_scale, 0.01,
              "V = this * box diagonal * MLP output (see motion_field.h).");
// Pretraining.
DEFINE_string(solver, "adam",
              "Pretraining solver: adam (mini-batches), lbfgs (Ceres "
              "GradientProblemSolver), lm (Ceres LM, small fields only).");
DEFINE_int32(iterations, 2000, "Adam steps or LBFGS / LM iterations.");
DEFINE_int32(batch_size, 8192, "Adam mini-batch; LM's batch.");
DEFINE_double(lr_triplane, 1e-2, "Adam learning rate of the planes.");
DEFINE_double(lr_mlp, 1e-3, "Adam learning rate of the MLP.");
DEFINE_double(final_lr_factor, 0.1, "Learning rates decay to this factor.");
DEFINE_double(tv_weight, 1.0,
              "Total variation weight on the planes, relative to the mean "
              "squared sample speed: V extrapolates smoothly where no "
              "sample lies (0: off).");
DEFINE_int32(lbfgs_max_samples, 200000,
             "LBFGS fits a random subset of at most this many samples.");
DEFINE_string(device, "cpu", es::kDeviceFlagHelp);
DEFINE_int32(seed, 1, "Seed of the field's initialization and sampling.");
DEFINE_int32(log_every, 100, "Print pretraining progress this often.");
DEFINE_bool(profile, false,
            "Print where the time goes, per stage (optical flow and "
            "lifting, then per pretraining iteration: scene-flow loss, "
            "fields forward / backward, Adam), after the pretraining.");

namespace {

es::PlaneCombination ParseCombination(const std::string& name) {
  if (name == "product") return es::PlaneCombination::kProduct;
  if (name == "sum") return es::PlaneCombination::kSum;
  if (name == "concat") return es::PlaneCombination::kConcat;
  throw es::InputError("unknown --combination '" + name +
                       "'; available: product, sum, concat");
}

// The part of the truth --oracle_velocity asks for; none: the flow's own.
std::optional<es::TruthPart> OracleTruthPart() {
  if (FLAGS_oracle_velocity == "none") return std::nullopt;
  if (FLAGS_oracle_velocity == "seen") return es::TruthPart::kSeen;
  if (FLAGS_oracle_velocity == "full") return es::TruthPart::kFull;
  throw es::InputError("--oracle_velocity must be none, seen or full, not '" +
                       FLAGS_oracle_velocity + "'");
}

void CheckFlags() {
  es::RequireFlag("scene", FLAGS_scene);
  es::RequirePositive("image_scale", FLAGS_image_scale);
  es::RequireAtLeast("stride", FLAGS_stride, 1);
  es::RequireAtLeast("frame_gap", FLAGS_frame_gap, 1);
  es::RequireAtLeast("iterations", FLAGS_iterations, 0);
  es::RequireAtLeast("batch_size", FLAGS_batch_size, 1);
  es::RequireAtLeast("max_samples", FLAGS_max_samples, 1);
  es::RequireAtLeast("lbfgs_max_samples", FLAGS_lbfgs_max_samples, 1);
  es::RequireAtLeast("log_every", FLAGS_log_every, 0);
  es::RequireAtLeast("triplane_res", FLAGS_triplane_res, 2);
  es::RequireAtLeast("triplane_channels", FLAGS_triplane_channels, 1);
  es::RequireAtLeast("mlp_width", FLAGS_mlp_width, 1);
  es::RequireAtLeast("mlp_depth", FLAGS_mlp_depth, 0);
  es::RequirePositive("velocity_scale", FLAGS_velocity_scale);
  es::RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  es::RequireInRange("line_of_sight_weight", FLAGS_line_of_sight_weight, 0, 1);
  es::RequireInRange("water_threshold", FLAGS_water_threshold, 0, 1);
  es::RequireInRange("min_alpha", FLAGS_min_alpha, 0, 1);
  es::RequireInRange("final_lr_factor", FLAGS_final_lr_factor, 0, 1);
  es::RequirePositive("max_fb_px", FLAGS_max_fb_px);
  es::RequirePositive("max_depth_jump", FLAGS_max_depth_jump);
  es::RequireNonNegative("tv_weight", FLAGS_tv_weight);
  OracleTruthPart();
}

// --device's pretraining, checked before the optical flow is computed: the
// CUDA device fits V with Adam only.
es::FlowPretrainer PretrainerFromFlags() {
  std::string device_name;
  const es::ComputeDevice device =
      es::ParseDeviceFlag(FLAGS_device, &device_name);
  if (device == es::ComputeDevice::kCuda) {
    if (es::ParsePretrainSolver(FLAGS_solver) != es::PretrainSolver::kAdam)
      throw es::InputError("--device cuda pretrains with --solver adam only, "
                           "not " + FLAGS_solver + "; use --device cpu");
    std::printf("pretraining on %s\n", device_name.c_str());
  }
  return es::FlowPretrainerOn(device);
}

// Keeps a random subset of at most `max` samples.
void Subsample(int max, uint32_t seed,
               std::vector<es::SceneFlowSample>* samples) {
  if (static_cast<int>(samples->size()) <= max) return;
  std::mt19937 rng(seed);
  std::shuffle(samples->begin(), samples->end(), rng);
  samples->resize(max);
}

// Seconds left when `done` of `total` equal steps took `seconds`.
double Eta(double seconds, int done, int total) {
  return done > 0 ? seconds / done * (total - done) : 0;
}

es::SceneFlowOptions SceneFlowOptionsFromFlags() {
  es::SceneFlowOptions o;
  o.method = es::ParseFlowMethod(FLAGS_flow);
  o.image = es::ParseFlowImage(FLAGS_flow_image);
  if (FLAGS_white_background) o.render.background.setOnes();
  o.water = es::ParseWaterSource(FLAGS_water_source);
  o.lifting.stride = FLAGS_stride;
  o.lifting.second_end = es::ParseSecondEnd(FLAGS_second_end);
  o.lifting.max_fb_error_px = FLAGS_max_fb_px;
  o.lifting.max_rel_depth_jump = FLAGS_max_depth_jump;
  o.lifting.water_threshold = FLAGS_water_threshold;
  o.lifting.frame_gap = FLAGS_frame_gap;
  o.lifting.line_of_sight_weight =
      FLAGS_free_line_of_sight ? FLAGS_line_of_sight_weight : 1.0;
  o.min_alpha = FLAGS_min_alpha;
  o.use_test_frames = FLAGS_use_test_frames;
  const auto start = std::chrono::steady_clock::now();
  o.progress = [start](int k, int n, const std::string& a,
                       const std::string& b, long count) {
    const double seconds = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();
    std::printf("flow %d/%d %s -> %s: %ld samples  ETA %.0f s\n", k + 1, n,
                a.c_str(), b.c_str(), count, Eta(seconds, k + 1, n));
    std::fflush(stdout);
  };
  return o;
}

// Progress lines (and history rows) come from PretrainField.
es::FlowPretrainOptions PretrainOptionsFromFlags() {
  es::FlowPretrainOptions o;
  o.solver = es::ParsePretrainSolver(FLAGS_solver);
  o.iterations = FLAGS_iterations;
  o.batch_size = FLAGS_batch_size;
  o.lr_triplane = FLAGS_lr_triplane;
  o.lr_mlp = FLAGS_lr_mlp;
  o.final_lr_factor = FLAGS_final_lr_factor;
  o.tv_weight = FLAGS_tv_weight;
  o.lbfgs_max_samples = FLAGS_lbfgs_max_samples;
  o.seed = FLAGS_seed;
  o.log_every = FLAGS_log_every;
  return o;
}

es::MotionFieldOptions FieldOptionsFromFlags() {
  es::MotionFieldOptions o;
  o.triplane.resolution = FLAGS_triplane_res;
  o.triplane.channels = FLAGS_triplane_channels;
  o.triplane.combination = ParseCombination(FLAGS_combination);
  o.mlp_width = FLAGS_mlp_width;
  o.mlp_depth = FLAGS_mlp_depth;
  o.velocity_scale = FLAGS_velocity_scale;
  o.seed = FLAGS_seed;
  return o;
}

// Lifts the optical flow of the scene's water to 3D samples (at most
// --max_samples); throws InputError when none survives.
es::SceneFlowResult LiftWaterFlow(const es::Scene& scene,
                                  const es::GaussianSet& model) {
  es::SceneFlowResult lifted;
  {
    es::ScopedStage timer(es::Stage::kOpticalFlow);
    lifted = es::LiftSceneFlow(scene, model, SceneFlowOptionsFromFlags());
  }
  const es::LiftingStats& s = lifted.stats;
  std::printf(
      "water pixels from %s; %ld candidates: %ld accepted, rejected %ld no "
      "depth, %ld depth edge, %ld outside, %ld inconsistent, %ld not water\n",
      lifted.used_masks ? "masks" : "the model's dynamic channel",
      s.candidates, s.accepted, s.no_depth, s.depth_edge, s.outside,
      s.inconsistent, s.not_water);
  if (lifted.samples.empty()) {
    throw es::InputError(
        FLAGS_scene +
        ": no scene-flow sample survived the checks (see the counts above); "
        "loosen --max_fb_px / --max_depth_jump or check the water masks. "
        "Nothing was written.");
  }
  Subsample(FLAGS_max_samples, FLAGS_seed, &lifted.samples);
  if (const std::optional<es::TruthPart> part = OracleTruthPart()) {
    es::ReplaceWithTruth(es::LoadMotionGt(FLAGS_scene), *part,
                         &lifted.samples);
    std::printf("--oracle_velocity %s: every sample now has the true "
                "velocity at its position\n",
                FLAGS_oracle_velocity.c_str());
  }
  return lifted;
}

// Fits V, spanning the dynamic Gaussians' box, to the lifted samples; one
// progress line (with ETA) and one <out>/flow_history.csv row per log.
es::FlowPretrainReport PretrainField(es::FlowPretrainer pretrain,
                                     const es::SceneFlowResult& lifted,
                                     const es::GaussianSet& model,
                                     const std::vector<int>& dynamic,
                                     es::TrainingHistory* history,
                                     es::MotionField* field) {
  Eigen::Vector3d lo, hi;
  es::FieldBox(model, dynamic, &lo, &hi);
  field->SetBox(lo, hi);
  es::FlowPretrainOptions fit_options = PretrainOptionsFromFlags();
  const int iterations = fit_options.iterations;
  fit_options.progress = [history, iterations](int it, double seconds,
                                               double rmse) {
    std::printf("pretrain iteration %d/%d  %.1f s  batch rmse %.3g  ETA "
                "%.0f s\n",
                it, iterations, seconds, rmse, Eta(seconds, it, iterations));
    std::fflush(stdout);
    history->Add(it, seconds, {rmse});
  };
  const es::FlowPretrainReport fit =
      pretrain(lifted.samples, fit_options, field);
  std::printf("fit rmse %.4g (targets rms %.4g, start %.4g) in %.1f s\n",
              fit.fit_rmse, fit.target_rms, fit.initial_rmse, fit.seconds);
  return fit;
}

// flow_metrics.json: the fit, the lifting counts and timings, and the
// ground-truth errors when the scene has gt/.
void WriteFlowMetrics(const std::string& path, double seconds,
                      const es::FlowPretrainReport& fit,
                      const es::SceneFlowResult& lifted,
                      const es::GaussianSet& model,
                      const std::vector<int>& dynamic,
                      const es::MotionField& field) {
  const es::LiftingStats& s = lifted.stats;
  nlohmann::ordered_json json = {
      {"num_samples", fit.num_samples},
      {"seconds", seconds},
      {"fit_rmse", fit.fit_rmse},
      {"target_rms", fit.target_rms},
      {"initial_rmse", fit.initial_rmse},
      {"flow", FLAGS_flow},
      {"flow_image", FLAGS_flow_image},
      {"second_end", FLAGS_second_end},
      {"frame_gap", FLAGS_frame_gap},
      {"free_line_of_sight", FLAGS_free_line_of_sight},
      {"line_of_sight_weight", FLAGS_line_of_sight_weight},
      {"tv_weight", FLAGS_tv_weight},
      {"oracle_velocity", FLAGS_oracle_velocity},
      {"solver", FLAGS_solver},
      {"iterations", fit.iterations},
      {"num_pairs", lifted.num_pairs},
      {"num_dynamic", dynamic.size()},
      {"water_from_masks", lifted.used_masks},
      {"candidates", s.candidates},
      {"rejected_no_depth", s.no_depth},
      {"rejected_depth_edge", s.depth_edge},
      {"rejected_outside", s.outside},
      {"rejected_inconsistent", s.inconsistent},
      {"rejected_not_water", s.not_water},
      {"render_seconds", lifted.render_seconds},
      {"flow_seconds", lifted.flow_seconds},
      {"lift_seconds", lifted.lift_seconds},
      {"pretrain_seconds", fit.seconds}};
  if (es::HasMotionGt(FLAGS_scene)) {
    std::vector<Eigen::Vector3d> points;
    for (int i : dynamic) {
      points.emplace_back(model.means[3 * i], model.means[3 * i + 1],
                          model.means[3 * i + 2]);
    }
    const es::VelocityFunction truth = es::LoadMotionGt(FLAGS_scene);
    const es::MotionGtMetrics gt =
        es::EvaluateMotionGt(field, points, truth);
    const es::MotionGtMetrics lifted_gt =
        es::EvaluateSamplesGt(lifted.samples, truth);
    std::printf("ground truth: epe %.4g (mean speed %.4g, relative %.3f, "
                "speed ratio %.2f); lifted samples: relative %.3f, speed "
                "ratio %.2f\n",
                gt.epe, gt.mean_speed, gt.rel_epe, gt.speed_ratio,
                lifted_gt.rel_epe, lifted_gt.speed_ratio);
    json["epe_gt"] = gt.epe;
    json["rel_epe_gt"] = gt.rel_epe;
    json["mean_speed_gt"] = gt.mean_speed;
    json["speed_ratio_gt"] = gt.speed_ratio;
    json["samples_rel_epe_gt"] = lifted_gt.rel_epe;
    json["samples_speed_ratio_gt"] = lifted_gt.speed_ratio;
  }
  es::WriteJsonFile(path, json);
}

int Run() {
  CheckFlags();
  const es::FlowPretrainer pretrain = PretrainerFromFlags();
  if (OracleTruthPart() && !es::HasMotionGt(FLAGS_scene)) {
    throw es::InputError(FLAGS_scene + "/gt/velocity_grid.bin: missing; "
                         "--oracle_velocity needs a synthetic scene with "
                         "ground-truth motion (es_synth). Nothing was "
                         "written.");
  }
  const auto start = std::chrono::steady_clock::now();
  const std::string static_path = FLAGS_static.empty()
                                      ? FLAGS_scene + "/static.ply"
                                      : FLAGS_static;
  const std::string out_dir = FLAGS_out.empty() ? FLAGS_scene : FLAGS_out;
  const es::MotionFieldOptions field_options = FieldOptionsFromFlags();

  es::PrepareOutputDirectory(out_dir, FLAGS_out.empty() ? "scene" : "out");
  es::SceneOptions scene_options;
  scene_options.image_scale = FLAGS_image_scale;
  const es::Scene scene = es::LoadScene(FLAGS_scene, scene_options);
  const es::GaussianSet model = es::ReadPly(static_path);
  const std::vector<int> dynamic =
      es::DynamicSet(model, FLAGS_dynamic_threshold);
  if (dynamic.empty()) {
    throw es::InputError(
        static_path + ": no dynamic Gaussians (sigmoid(dynamic_logit) > " +
        std::to_string(FLAGS_dynamic_threshold) +
        "), so there is no water for a motion field; train Stage 1 with "
        "water masks or lower --dynamic_threshold. Nothing was written.");
  }
  std::printf("%d frames, %d of %d Gaussians dynamic\n",
              static_cast<int>(scene.frames.size()),
              static_cast<int>(dynamic.size()), model.size());
  es::StageProfile::Get().Start(FLAGS_profile);
  const es::SceneFlowResult lifted = LiftWaterFlow(scene, model);

  es::MotionField field(field_options);
  es::TrainingHistory history(out_dir + "/flow_history.csv", {"rmse"});
  const es::FlowPretrainReport fit =
      PretrainField(pretrain, lifted, model, dynamic, &history, &field);
  es::StageProfile::Get().PrintAndStop(
      "es_flowinit, " + std::to_string(FLAGS_iterations) +
      " pretraining iterations of " + std::to_string(FLAGS_batch_size) +
      " samples (optical flow + lifting: once, before them)");

  es::SaveMotionField(field, out_dir + "/motion_field.bin");
  es::SaveSceneFlowSamples(lifted.samples,
                           out_dir + "/scene_flow_samples.bin");
  history.Write();
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  WriteFlowMetrics(out_dir + "/flow_metrics.json", seconds, fit, lifted,
                   model, dynamic, field);
  std::printf("wrote %s/motion_field.bin, scene_flow_samples.bin, "
              "flow_metrics.json and flow_history.csv (%.1f s)\n",
              out_dir.c_str(), seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return es::RunApp(
      argc, argv,
      "Stage 2: motion-field initialization from optical flow.\n"
      "  es_flowinit --scene DIR [--static DIR/static.ply] [--out DIR]\n"
      "              [--flow dis|farneback|...] [--solver adam|lbfgs|lm]\n"
      "              [--device cpu|cuda]\n"
      "Lifts the optical flow of training frames --frame_gap apart (by "
      "default of each frame minus the static model's render of it) to 3D "
      "with the static model's depth, keeps water pixels (masks/ or the "
      "model's dynamic channel), pretrains V on them and writes <out>/"
      "motion_field.bin, scene_flow_samples.bin (the samples; es_train "
      "--flow_prior_weight keeps them as a prior), flow_history.csv and "
      "flow_metrics.json (epe_gt, rel_epe_gt when the scene has gt/). "
      "Exits 1 and writes nothing when the model has no dynamic Gaussians "
      "or no sample survives.",
      Run);
}
