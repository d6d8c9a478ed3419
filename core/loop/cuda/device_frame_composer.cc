#include "core/loop/cuda/device_frame_composer.h"

#include <glog/logging.h>

#include "core/fields/residual_field.h"
#include "core/loop/cuda/compose_kernels.h"
#include "core/loop/cuda/euler_kernels.h"
#include "core/loop/cycle_time.h"
#include "core/model/gaussians.h"

namespace es {
namespace cuda {
DeviceFrameComposer::DeviceFrameComposer(const EulerOptions& euler_options)
    : euler_options_(euler_options) {}

DeviceFrameComposer::FieldKey DeviceFrameComposer::KeyOf(
    const MotionField* field) {
  return {field,
          field->triplane().num_params(),
          field->mlp().num_params(),
          field->triplane().box_min(),
          field->triplane().box_max(),
          field->output_scale()};
}

DeviceFrameComposer::FieldKey DeviceFrameComposer::KeyOf(
    const ResidualField* field) {
  return {field,
          field->triplane().num_params(),
          field->mlp().num_params(),
          field->triplane().box_min(),
          field->triplane().box_max(),
          field->options().position_scale};
}

void DeviceFrameComposer::SetStructure(const LoopStructure& s) {
  CHECK(s.dynamic_index != nullptr && s.start_times != nullptr)
      << "LoopStructure without a dynamic set or start times";
  const std::vector<int>& dynamic = *s.dynamic_index;
  CHECK_EQ(dynamic.size(), s.start_times->size())
      << "one start time per dynamic Gaussian";
  CHECK_GT(s.cycle_length, 0) << "cycle length";
  if (dynamic != dynamic_host_ || s.count != slot_count_) {
    std::vector<int> slot(s.count, -1);
    for (size_t k = 0; k < dynamic.size(); ++k) {
      const int n = dynamic[k];
      CHECK(n >= 0 && n < s.count && (k == 0 || n > dynamic[k - 1]))
          << "dynamic index " << n << " (entry " << k
          << ") is not an ascending index below the " << s.count
          << " Gaussians";
      slot[n] = static_cast<int>(k);
    }
    dynamic_.Upload(dynamic);
    slot_.Upload(slot);
    dynamic_host_ = dynamic;
    slot_count_ = s.count;
    cycles_uploaded_ = false;
    backward_ready_ = false;
  }
  num_dynamic_ = static_cast<int>(dynamic.size());
  if (s.motion == nullptr) {
    chain_.reset();
    motion_.reset();
  } else if (!motion_ || !(KeyOf(s.motion) == motion_key_)) {
    chain_.reset();  // points at the old field
    motion_.emplace(*s.motion);
    chain_.emplace(&*motion_, euler_options_);
    motion_key_ = KeyOf(s.motion);
    backward_ready_ = false;
  }
  if (s.residual == nullptr) {
    residual_.reset();
  } else if (!residual_ || !(KeyOf(s.residual) == residual_key_)) {
    residual_.emplace(*s.residual);
    residual_key_ = KeyOf(s.residual);
    backward_ready_ = false;
  }
  structure_ = s;
}

void DeviceFrameComposer::SetFrame(int frame,
                                   std::optional<int> cycle_number) {
  const int m = num_dynamic_;
  const int* start = structure_.start_times->data();
  const int length = structure_.cycle_length;
  bool changed =
      !cycles_uploaded_ || static_cast<int>(cycle_index_.size()) != m;
  cycle_index_.resize(m);
  cycle_number_.resize(m);
  for (int k = 0; k < m; ++k) {
    const int t = CycleIndex(frame, start[k], length);
    const int p =
        cycle_number ? *cycle_number : CycleNumber(frame, start[k], length);
    changed = changed || t != cycle_index_[k] || p != cycle_number_[k];
    cycle_index_[k] = t;
    cycle_number_[k] = p;
  }
  if (!changed) return;
  cycle_index_device_.Upload(cycle_index_);
  cycle_number_device_.Upload(cycle_number_);
  cycles_uploaded_ = true;
}

const DeviceSplatView& DeviceFrameComposer::Compose(
    const DeviceLoopModelView& model, int frame,
    std::optional<int> cycle_number) {
  CHECK(structure_.dynamic_index != nullptr) << "SetStructure before Compose";
  const DeviceSplatView& c = model.canonical;
  CHECK(c.count == structure_.count && c.sh_degree == structure_.sh_degree)
      << "splats of " << c.count << " Gaussians, degree " << c.sh_degree
      << ", for a structure of " << structure_.count << ", degree "
      << structure_.sh_degree;
  euler_stats_ = EulerStats();
  backward_ready_ = true;
  const int m = num_dynamic_;
  DeviceDynamicFrame dynamic;
  if (m > 0) {
    SetFrame(frame, cycle_number);
    x0_.Resize(3 * static_cast<size_t>(m));
    GatherDynamicMeansKernel(m, dynamic_.data(), c.means, x0_.data());
    dynamic = {m, dynamic_.data(), x0_.data(), x0_.data(),
               cycle_index_device_.data(), cycle_number_device_.data()};
    if (chain_) {
      positions_.Resize(3 * static_cast<size_t>(m));
      chain_->Forward(model.motion_params, m, x0_.data(),
                      cycle_index_.data(), positions_.data());
      euler_stats_ = chain_->stats();
      dynamic.positions = positions_.data();
    }
  }
  return assembly_.Assemble(c, dynamic, residual_ ? &*residual_ : nullptr,
                            model.residual_params);
}

void DeviceFrameComposer::Backward(const DeviceLoopModelView& model,
                                   const DeviceSplatGradients& grads,
                                   const double* d_residuals,
                                   const LoopModelGradients& out) {
  CHECK(backward_ready_)
      << "DeviceFrameComposer::Backward without a matching Compose";
  const DeviceSplatView& c = model.canonical;
  const int count = c.count;
  const int m = num_dynamic_;
  const int coeffs = NumShCoeffs(c.sh_degree);
  auto add = [](long long n, const double* g, double* dst) {
    if (dst != nullptr) AddDoublesKernel(n, g, dst);
  };
  // Scales and rotations pass unchanged, opacity and SH past D's additive
  // offsets.
  add(3LL * count, grads.log_scales, out.log_scales);
  add(4LL * count, grads.quats, out.quats);
  add(count, grads.opacity_logits, out.opacity_logits);
  add(3LL * coeffs * count, grads.sh, out.sh);
  if (m == 0) {
    add(3LL * count, grads.means, out.means);
    return;
  }
  d_positions_.Resize(3 * static_cast<size_t>(m));
  double* d_outputs = nullptr;
  if (residual_) {
    d_residuals_.Resize(static_cast<size_t>(m) * kResidualDim);
    d_outputs = d_residuals_.data();
  }
  ComposeBackwardKernel(m, dynamic_.data(), grads.means, grads.opacity_logits,
                        grads.sh, kResidualLayout, coeffs,
                        OffsetShCoeffs(kResidualLayout, coeffs), d_residuals,
                        d_positions_.data(), d_outputs);
  double* d_x0 = nullptr;
  if (out.means != nullptr) {
    d_x0_.Resize(3 * static_cast<size_t>(m));
    d_x0_.Zero();
    d_x0 = d_x0_.data();
  }
  // D, then V through the Euler chain, as FrameComposer::FieldsBackward.
  if (residual_) {
    residual_->Backward(model.residual_params, d_outputs, out.residual, d_x0,
                        assembly_.residual_workspace());
  }
  if (chain_) {
    chain_->Backward(model.motion_params, d_positions_.data(), out.motion,
                     d_x0);
  } else if (d_x0 != nullptr) {
    AddDoublesKernel(3LL * m, d_positions_.data(), d_x0);
  }
  if (out.means != nullptr) {
    AddMeansGradientKernel(count, slot_.data(), grads.means, d_x0, out.means);
  }
}

}  // namespace cuda
}  // namespace es
