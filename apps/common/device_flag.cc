#include "apps/common/device_flag.h"

#include "core/base/input_error.h"
#include "solvers/train/joint_trainer.h"

#ifdef ES_HAVE_CUDA
#include "core/base/cuda/cuda_error.h"
#include "solvers/train/cuda/device_flow_pretrain.h"
#include "solvers/train/cuda/device_joint_trainer.h"
#include "solvers/train/cuda/device_static_trainer.h"
#endif

namespace es {

const char kDeviceFlagHelp[] =
    "Where training runs: cpu, or cuda (the first NVIDIA GPU; needs a "
    "build with the CUDA backend, -DES_CUDA=ON or AUTO with the CUDA "
    "toolkit installed). Parameters, gradients and images then stay on "
    "the GPU.";

ComputeDevice ParseDeviceFlag(const std::string& value,
                              std::string* description) {
  if (value == "cpu") {
    if (description != nullptr) *description = "CPU";
    return ComputeDevice::kCpu;
  }
  if (value != "cuda")
    throw InputError("--device must be cpu or cuda, not '" + value + "'");
#ifdef ES_HAVE_CUDA
  std::string why;
  if (!cuda::CudaDeviceAvailable(&why))
    throw InputError("--device cuda: no CUDA device found (" + why +
                     "); use --device cpu, or run where an NVIDIA GPU and "
                     "its driver are present");
  if (description != nullptr) *description = why;
  return ComputeDevice::kCuda;
#else
  throw InputError(
      "--device cuda: this build has no CUDA backend (configure with "
      "-DES_CUDA=ON where the CUDA toolkit is installed, nvcc on PATH or "
      "CMAKE_CUDA_COMPILER set, and rebuild); use --device cpu");
#endif
}

StaticTrainerFactory StaticTrainerOn(ComputeDevice device) {
#ifdef ES_HAVE_CUDA
  if (device == ComputeDevice::kCuda) return cuda::MakeDeviceStaticTrainer;
#endif
  return MakeStaticTrainer;
}

FlowPretrainer FlowPretrainerOn(ComputeDevice device) {
#ifdef ES_HAVE_CUDA
  if (device == ComputeDevice::kCuda) return cuda::PretrainMotionFieldOnDevice;
#endif
  return PretrainMotionField;
}

JointTrainerFactory JointTrainerOn(ComputeDevice device) {
#ifdef ES_HAVE_CUDA
  if (device == ComputeDevice::kCuda) return cuda::MakeDeviceJointTrainer;
#endif
  return MakeJointTrainer;
}

}  // namespace es
