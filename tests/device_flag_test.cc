// --device (apps/common/device_flag.h): cpu always works, an unknown value
// and cuda where it cannot run are InputErrors that say why; each device
// picks its own V pretraining.

#include "apps/common/device_flag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/base/input_error.h"

#ifdef ES_HAVE_CUDA
#include "core/base/cuda/cuda_error.h"
#include "solvers/train/cuda/device_flow_pretrain.h"
#endif

using ::testing::HasSubstr;

namespace es {
namespace {

std::string ErrorOf(const std::string& value) {
  try {
    ParseDeviceFlag(value);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DeviceFlagTest, CpuAlwaysWorks) {
  std::string description;
  EXPECT_EQ(ParseDeviceFlag("cpu", &description), ComputeDevice::kCpu);
  EXPECT_EQ(description, "CPU");
}

TEST(DeviceFlagTest, UnknownDevicesAreNamed) {
  EXPECT_EQ(ErrorOf("gpu"), "--device must be cpu or cuda, not 'gpu'");
  EXPECT_THAT(ErrorOf("CUDA"), HasSubstr("not 'CUDA'"));
  EXPECT_THAT(ErrorOf(""), HasSubstr("not ''"));
}

TEST(DeviceFlagTest, CudaWorksOnlyWithTheBackendAndADevice) {
#ifdef ES_HAVE_CUDA
  std::string why;
  if (cuda::CudaDeviceAvailable(&why)) {
    std::string description;
    EXPECT_EQ(ParseDeviceFlag("cuda", &description), ComputeDevice::kCuda);
    EXPECT_EQ(description, why);
  } else {
    EXPECT_THAT(ErrorOf("cuda"),
                HasSubstr("no CUDA device found (" + why + ")"));
  }
#else
  EXPECT_THAT(ErrorOf("cuda"), HasSubstr("this build has no CUDA backend"));
  EXPECT_THAT(ErrorOf("cuda"), HasSubstr("-DES_CUDA=ON"));
#endif
}

TEST(DeviceFlagTest, EachDevicePretrainsOnItsOwn) {
  EXPECT_EQ(FlowPretrainerOn(ComputeDevice::kCpu), &PretrainMotionField);
#ifdef ES_HAVE_CUDA
  EXPECT_EQ(FlowPretrainerOn(ComputeDevice::kCuda),
            &cuda::PretrainMotionFieldOnDevice);
#endif
}

}  // namespace
}  // namespace es
