#include "solvers/train/cuda/device_gaussians.h"

#include "solvers/train/cuda/training_kernels.h"

namespace es {
namespace cuda {

void DeviceGaussians::Upload(const GaussianSet& g) {
  g.CheckConsistent();
  count_ = g.size();
  sh_degree_ = g.sh_degree;
  for (int k = 0; k < kNumGaussianArrays; ++k)
    arrays_[k].Upload(g.*kGaussianArrays[k].values);
}

void DeviceGaussians::Download(GaussianSet* g) const {
  g->sh_degree = sh_degree_;
  for (int k = 0; k < kNumGaussianArrays; ++k)
    g->*kGaussianArrays[k].values = arrays_[k].Download();
}

void DeviceGaussians::ResizeZero(int count, int sh_degree) {
  count_ = count;
  sh_degree_ = sh_degree;
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    arrays_[k].Resize(
        static_cast<size_t>(kGaussianArrays[k].Width(NumShCoeffs(sh_degree))) *
        count);
    arrays_[k].Zero();
  }
}

DeviceGaussianBlocks DeviceGaussians::Blocks() {
  DeviceGaussianBlocks b;
  b.count = count_;
  b.sh_degree = sh_degree_;
  for (int k = 0; k < kNumGaussianArrays; ++k) b.arrays[k] = arrays_[k].data();
  return b;
}

std::vector<double*> DeviceGaussians::BlockPointers() {
  const DeviceGaussianBlocks b = Blocks();
  return {b.arrays.begin(), b.arrays.end()};
}

bool DeviceGaussians::AllFinite() {
  flag_.Resize(1);
  flag_.Zero();
  MarkNonFinite(flag_.data());
  int flag = 0;
  flag_.Download(&flag);
  return flag == 0;
}

void DeviceGaussians::MarkNonFinite(int* flag) {
  for (DeviceBuffer<double>& a : arrays_)
    FlagNonFinite(a.size(), a.data(), flag);
}

std::vector<double> DeviceGaussians::MaxMagnitudes() {
  magnitude_bits_.Resize(kNumGaussianArrays);
  magnitude_bits_.Zero();
  RaiseMaxMagnitudes(magnitude_bits_.data());
  std::vector<double> magnitudes;
  for (unsigned long long bits : magnitude_bits_.Download())
    magnitudes.push_back(MagnitudeOfBits(bits));
  return magnitudes;
}

void DeviceGaussians::RaiseMaxMagnitudes(unsigned long long* bits) {
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    RaiseMaxMagnitudeBits(static_cast<long long>(arrays_[k].size()),
                          arrays_[k].data(), bits + k);
  }
}

}  // namespace cuda
}  // namespace es
