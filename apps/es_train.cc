// Stage 3: joint training of the canonical splats, the motion field V and
// the residual field D on a scene, from the static model (es_static) and
// the pretrained V (es_flowinit).
//
//   es_train --scene DIR --init DIR --out DIR [--iterations 20000]
//            [--cycle_length 15] [--resume] [--device cpu|cuda] ...
//
// The flags are apps/common/joint_flags.cc's; the stage is RunJointStage
// (solvers/train/joint_stage.h).

#include <cstdio>

#include "apps/common/joint_flags.h"
#include "apps/common/world.h"
#include "solvers/train/joint_stage.h"

constexpr char kUsage[] =
    "Stage 3: joint training of the looping model.\n"
    "  es_train --scene DIR --init DIR --out DIR "
    "[--iterations N] [--cycle_length L] [--resume]\n"
    "           [--device cpu|cuda] [--batch_frames B]\n"
    "Writes the model (loop.txt, canonical.ply, fields), "
    "<out>/metrics.json, <out>/history.csv and "
    "<out>/joint_checkpoint.bin.";

int main(int argc, char** argv) {
  return es::RunAppOnRanks(argc, argv, kUsage, [](es::Communicator* comm) {
    es::ComputeDevice device;
    es::JointStageOptions options = es::JointStageOptionsFromFlags(&device);
    options.trainer.comm = comm;
    es::CheckBatchFramesFlag(options.trainer.batch_frames, *comm,
                             device == es::ComputeDevice::kCuda);
    const es::JointStageResult r =
        es::RunJointStage(options, es::JointTrainerOn(device));
    std::printf("test PSNR %.3f SSIM %.4f (water PSNR %.3f SSIM %.4f, "
                "scenery PSNR %.3f) over %d frames; %.1f s\n",
                r.test.psnr, r.test.ssim, r.test.psnr_water,
                r.test.ssim_water, r.test.psnr_static, r.test.frames,
                r.seconds);
    return 0;
  });
}
