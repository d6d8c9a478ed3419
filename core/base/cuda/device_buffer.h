#ifndef EULERSPLAT_CORE_BASE_CUDA_DEVICE_BUFFER_H_
#define EULERSPLAT_CORE_BASE_CUDA_DEVICE_BUFFER_H_

// An owning array in device memory, without CUDA types. Every call that
// fails throws CudaError (cuda_error.h).

#include <cstddef>
#include <utility>
#include <vector>

namespace es {
namespace cuda {

void* DeviceAllocate(size_t bytes);  // nullptr for 0 bytes
void DeviceFree(void* p);            // nullptr: nothing
void CopyToDevice(void* device, const void* host, size_t bytes);
void CopyToHost(void* host, const void* device, size_t bytes);
void DeviceZero(void* device, size_t bytes);

template <typename T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  explicit DeviceBuffer(size_t size) { Resize(size); }
  ~DeviceBuffer() { DeviceFree(data_); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& other) noexcept { *this = std::move(other); }
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    std::swap(capacity_, other.capacity_);
    return *this;
  }

  // Holds `size` elements afterwards; the allocation only grows (a frame's
  // buffers are reused by the next), and its contents are lost when it does.
  void Resize(size_t size) {
    if (size > capacity_) {
      DeviceFree(data_);
      data_ = nullptr;
      capacity_ = 0;
      data_ = static_cast<T*>(DeviceAllocate(size * sizeof(T)));
      capacity_ = size;
    }
    size_ = size;
  }
  void Upload(const T* host, size_t size) {
    Resize(size);
    CopyToDevice(data_, host, size * sizeof(T));
  }
  void Upload(const std::vector<T>& host) { Upload(host.data(), host.size()); }
  void Download(T* host) const { CopyToHost(host, data_, size_ * sizeof(T)); }
  std::vector<T> Download() const {
    std::vector<T> host(size_);
    Download(host.data());
    return host;
  }
  void Zero() { DeviceZero(data_, size_ * sizeof(T)); }

  T* data() { return data_; }
  const T* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  T* data_ = nullptr;
  size_t size_ = 0;
  size_t capacity_ = 0;
};

}  // namespace cuda
}  // namespace es

#endif  // EULERSPLAT_CORE_BASE_CUDA_DEVICE_BUFFER_H_
