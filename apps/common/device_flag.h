#ifndef EULERSPLAT_APPS_COMMON_DEVICE_FLAG_H_
#define EULERSPLAT_APPS_COMMON_DEVICE_FLAG_H_

// --device cpu|cuda, for the binaries whose stage has a CUDA path: what
// the flag accepts, its help text, and what each value runs.

#include <string>

#include "solvers/train/flow_pretrain.h"
#include "solvers/train/joint_stage_trainer.h"
#include "solvers/train/static_stage.h"

namespace es {

enum class ComputeDevice { kCpu, kCuda };

// The flag's help text (gflags' DEFINE_string(device, "cpu", ...)).
extern const char kDeviceFlagHelp[];

// Parses --device's value and checks that the device can be used. Throws
// InputError for an unknown value, for cuda in a build without the CUDA
// backend (saying how to build one) and for cuda with no usable device
// (saying why; under ES_CUDA_EMULATION the emulated device counts as
// present). If `description` is set it receives what runs ("CPU", or the
// GPU's name and memory).
ComputeDevice ParseDeviceFlag(const std::string& value,
                              std::string* description = nullptr);

// The Stage 1 trainer for a device.
StaticTrainerFactory StaticTrainerOn(ComputeDevice device);
// The Stage 2 V pretraining for a device.
FlowPretrainer FlowPretrainerOn(ComputeDevice device);
// The Stage 3 trainer for a device.
JointTrainerFactory JointTrainerOn(ComputeDevice device);

}  // namespace es

#endif  // EULERSPLAT_APPS_COMMON_DEVICE_FLAG_H_
