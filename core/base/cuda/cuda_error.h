#ifndef EULERSPLAT_CORE_BASE_CUDA_CUDA_ERROR_H_
#define EULERSPLAT_CORE_BASE_CUDA_CUDA_ERROR_H_

// Errors of the CUDA backend, without CUDA types (host code that only
// calls the backend includes this).

#include <stdexcept>
#include <string>

namespace es {
namespace cuda {

// A failed CUDA call: "CUDA error in FILE:LINE: CALL: the runtime's text".
class CudaError : public std::runtime_error {
 public:
  explicit CudaError(const std::string& message)
      : std::runtime_error(message) {}
};

[[noreturn]] void ThrowCudaError(const char* error_text, const char* call,
                                 const char* file, int line);

// Whether a CUDA device can run the backend's kernels; if not and `why` is
// set, *why says what is missing (no driver, no device, ...). On success
// *why is the device's description (CudaDeviceDescription).
bool CudaDeviceAvailable(std::string* why = nullptr);

// Name, compute capability and memory of the current device, e.g.
// "NVIDIA H200 (sm_90, 132 SMs, 139.8 GiB)".
std::string CudaDeviceDescription();

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_CUDA_CUDA_ERROR_H_
