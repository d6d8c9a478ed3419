#include "apps/common/flowinit_flags.h"

#include <cstdio>
#include <string>

#include <gflags/gflags.h>

#include "apps/common/flag_checks.h"
#include "core/base/input_error.h"
#include "core/base/parse_choice.h"
#include "solvers/train/data_parallel.h"

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
DEFINE_int32(batch_shards, 0,
             "Cut each Adam mini-batch into this many runs of samples, "
             "spread over the MPI ranks (mpiexec -n N es_flowinit ..., or "
             "eulersplat --ranks N), which sum their gradients; 0: one per "
             "rank. The fit depends on the shards, not on the ranks: one "
             "process with --batch_shards 2 fits what 2 ranks fit. CPU and "
             "--solver adam only.");
DEFINE_int32(log_every, 100, "Print pretraining progress this often.");
DEFINE_bool(profile, false,
            "Print where the time goes, per stage (optical flow and "
            "lifting, then per pretraining iteration: scene-flow loss, "
            "fields forward / backward, Adam), after the pretraining.");

namespace es {
namespace {

PlaneCombination ParseCombination(const std::string& name) {
  return ParseChoice<PlaneCombination>(
      "--combination", name, {{"product", PlaneCombination::kProduct},
                              {"sum", PlaneCombination::kSum},
                              {"concat", PlaneCombination::kConcat}});
}

SceneFlowOptions SceneFlowOptionsFromFlags() {
  SceneFlowOptions o;
  o.method = ParseFlowMethod(FLAGS_flow);
  o.image = ParseFlowImage(FLAGS_flow_image);
  if (FLAGS_white_background) o.render.background.setOnes();
  o.water = ParseWaterSource(FLAGS_water_source);
  o.lifting.stride = FLAGS_stride;
  o.lifting.second_end = ParseSecondEnd(FLAGS_second_end);
  o.lifting.max_fb_error_px = FLAGS_max_fb_px;
  o.lifting.max_rel_depth_jump = FLAGS_max_depth_jump;
  o.lifting.water_threshold = FLAGS_water_threshold;
  o.lifting.frame_gap = FLAGS_frame_gap;
  o.lifting.line_of_sight_weight = FLAGS_line_of_sight_weight;
  o.min_alpha = FLAGS_min_alpha;
  o.use_test_frames = FLAGS_use_test_frames;
  return o;
}

FlowPretrainOptions PretrainOptionsFromFlags() {
  FlowPretrainOptions o;
  o.solver = ParsePretrainSolver(FLAGS_solver);
  o.iterations = FLAGS_iterations;
  o.batch_size = FLAGS_batch_size;
  o.lr_triplane = FLAGS_lr_triplane;
  o.lr_mlp = FLAGS_lr_mlp;
  o.final_lr_factor = FLAGS_final_lr_factor;
  o.tv_weight = FLAGS_tv_weight;
  o.lbfgs_max_samples = FLAGS_lbfgs_max_samples;
  o.seed = FLAGS_seed;
  o.log_every = FLAGS_log_every;
  o.shards = FLAGS_batch_shards;
  return o;
}

MotionFieldOptions FieldOptionsFromFlags() {
  MotionFieldOptions o;
  o.triplane.resolution = FLAGS_triplane_res;
  o.triplane.channels = FLAGS_triplane_channels;
  o.triplane.combination = ParseCombination(FLAGS_combination);
  o.mlp_width = FLAGS_mlp_width;
  o.mlp_depth = FLAGS_mlp_depth;
  o.velocity_scale = FLAGS_velocity_scale;
  o.seed = FLAGS_seed;
  return o;
}

}  // namespace

void CheckFlowInitFlags() {
  RequireFlag("scene", FLAGS_scene);
  RequirePositive("image_scale", FLAGS_image_scale);
  RequireAtLeast("stride", FLAGS_stride, 1);
  RequireAtLeast("frame_gap", FLAGS_frame_gap, 1);
  RequireAtLeast("iterations", FLAGS_iterations, 0);
  RequireAtLeast("batch_size", FLAGS_batch_size, 1);
  RequireAtLeast("max_samples", FLAGS_max_samples, 1);
  RequireAtLeast("lbfgs_max_samples", FLAGS_lbfgs_max_samples, 1);
  RequireAtLeast("log_every", FLAGS_log_every, 0);
  RequireAtLeast("batch_shards", FLAGS_batch_shards, 0);
  RequireAtLeast("triplane_res", FLAGS_triplane_res, 2);
  RequireAtLeast("triplane_channels", FLAGS_triplane_channels, 1);
  RequireAtLeast("mlp_width", FLAGS_mlp_width, 1);
  RequireAtLeast("mlp_depth", FLAGS_mlp_depth, 0);
  RequirePositive("velocity_scale", FLAGS_velocity_scale);
  RequireInOpenRange("dynamic_threshold", FLAGS_dynamic_threshold, 0, 1);
  RequireInRange("line_of_sight_weight", FLAGS_line_of_sight_weight, 0, 1);
  RequireInRange("water_threshold", FLAGS_water_threshold, 0, 1);
  RequireInRange("min_alpha", FLAGS_min_alpha, 0, 1);
  RequireInRange("final_lr_factor", FLAGS_final_lr_factor, 0, 1);
  RequirePositive("max_fb_px", FLAGS_max_fb_px);
  RequirePositive("max_depth_jump", FLAGS_max_depth_jump);
  RequireNonNegative("tv_weight", FLAGS_tv_weight);
  ParseOracleVelocity(FLAGS_oracle_velocity);
}

FlowPretrainer FlowPretrainerFromFlags(const Communicator& comm) {
  std::string device_name;
  const ComputeDevice device = ParseDeviceFlag(FLAGS_device, &device_name);
  if (FLAGS_batch_shards != 0) {
    CheckBatchFrames(FLAGS_batch_shards, comm, "--batch_shards");
  }
  if (comm.size() > 1 || FLAGS_batch_shards > 1) {
    if (device != ComputeDevice::kCpu)
      throw InputError("several ranks or --batch_shards: V is pretrained "
                       "data-parallel on the CPU only (--device cpu)");
    if (ParsePretrainSolver(FLAGS_solver) != PretrainSolver::kAdam)
      throw InputError("several ranks or --batch_shards: V is pretrained "
                       "data-parallel with --solver adam only, not " +
                       FLAGS_solver);
  }
  if (device == ComputeDevice::kCuda) {
    if (ParsePretrainSolver(FLAGS_solver) != PretrainSolver::kAdam)
      throw InputError("--device cuda pretrains with --solver adam only, "
                       "not " + FLAGS_solver + "; use --device cpu");
    std::printf("pretraining on %s\n", device_name.c_str());
  }
  return FlowPretrainerOn(device);
}

FlowInitStageOptions FlowInitStageOptionsFromFlags() {
  FlowInitStageOptions o;
  o.scene_dir = FLAGS_scene;
  o.static_path = FLAGS_static;
  o.out_dir = FLAGS_out;
  o.scene.image_scale = FLAGS_image_scale;
  o.flow = SceneFlowOptionsFromFlags();
  o.free_line_of_sight = FLAGS_free_line_of_sight;
  o.max_samples = FLAGS_max_samples;
  o.sample_seed = FLAGS_seed;
  o.oracle = ParseOracleVelocity(FLAGS_oracle_velocity);
  o.dynamic_threshold = FLAGS_dynamic_threshold;
  o.field = FieldOptionsFromFlags();
  o.pretrain = PretrainOptionsFromFlags();
  o.profile = FLAGS_profile;
  return o;
}

}  // namespace es
