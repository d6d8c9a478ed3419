#include "solvers/train/cuda/device_gaussians.h"

#include "solvers/train/cuda/training_kernels.h"

namespace es {
namespace cuda {

void DeviceGaussians::Upload(const GaussianSet& g) {
  g.CheckConsistent();
  count_ = g.size();
  sh_degree_ = g.sh_degree;
  means_.Upload(g.means);
  log_scales_.Upload(g.log_scales);
  quats_.Upload(g.quats);
  opacity_logits_.Upload(g.opacity_logits);
  sh_.Upload(g.sh);
  dynamic_logits_.Upload(g.dynamic_logits);
}

void DeviceGaussians::Download(GaussianSet* g) const {
  g->sh_degree = sh_degree_;
  g->means = means_.Download();
  g->log_scales = log_scales_.Download();
  g->quats = quats_.Download();
  g->opacity_logits = opacity_logits_.Download();
  g->sh = sh_.Download();
  g->dynamic_logits = dynamic_logits_.Download();
}

void DeviceGaussians::ResizeZero(int count, int sh_degree) {
  count_ = count;
  sh_degree_ = sh_degree;
  const size_t n = count;
  means_.Resize(3 * n);
  log_scales_.Resize(3 * n);
  quats_.Resize(4 * n);
  opacity_logits_.Resize(n);
  sh_.Resize(3 * static_cast<size_t>(NumShCoeffs(sh_degree)) * n);
  dynamic_logits_.Resize(n);
  for (DeviceBuffer<double>* a : Arrays()) a->Zero();
}

DeviceGaussianBlocks DeviceGaussians::Blocks() {
  DeviceGaussianBlocks b;
  b.count = count_;
  b.sh_degree = sh_degree_;
  b.means = means_.data();
  b.log_scales = log_scales_.data();
  b.quats = quats_.data();
  b.opacity_logits = opacity_logits_.data();
  b.sh = sh_.data();
  b.dynamic_logits = dynamic_logits_.data();
  return b;
}

std::vector<double*> DeviceGaussians::BlockPointers() {
  return {means_.data(),          log_scales_.data(), quats_.data(),
          opacity_logits_.data(), sh_.data(),         dynamic_logits_.data()};
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
  for (DeviceBuffer<double>* a : Arrays())
    FlagNonFinite(a->size(), a->data(), flag);
}

std::vector<double> DeviceGaussians::MaxMagnitudes() {
  magnitude_bits_.Resize(6);
  magnitude_bits_.Zero();
  RaiseMaxMagnitudes(magnitude_bits_.data());
  std::vector<double> magnitudes;
  for (unsigned long long bits : magnitude_bits_.Download())
    magnitudes.push_back(MagnitudeOfBits(bits));
  return magnitudes;
}

void DeviceGaussians::RaiseMaxMagnitudes(unsigned long long* bits) {
  const std::vector<DeviceBuffer<double>*> arrays = Arrays();
  for (size_t k = 0; k < arrays.size(); ++k) {
    RaiseMaxMagnitudeBits(static_cast<long long>(arrays[k]->size()),
                          arrays[k]->data(), bits + k);
  }
}

std::vector<DeviceBuffer<double>*> DeviceGaussians::Arrays() {
  return {&means_,          &log_scales_, &quats_,
          &opacity_logits_, &sh_,         &dynamic_logits_};
}

}  // namespace cuda
}  // namespace es
