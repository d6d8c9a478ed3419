#include "core/loop/cuda/device_splat_assembly.h"

#include "core/loop/cuda/euler_kernels.h"
#include "core/model/gaussians.h"

namespace es {
namespace cuda {

const DeviceSplatView& DeviceSplatAssembly::Assemble(
    const DeviceSplatView& canonical, const DeviceDynamicFrame& dynamic,
    const DeviceResidualField* residual, const FieldParams& residual_params) {
  view_ = canonical;
  has_residuals_ = false;
  const int m = dynamic.count;
  if (m == 0) return view_;
  const int count = canonical.count;
  const int coeffs = NumShCoeffs(canonical.sh_degree);
  means_.Resize(3 * static_cast<size_t>(count));
  CopyDoublesKernel(3LL * count, canonical.means, means_.data());
  view_.means = means_.data();
  double* opacity_logits = nullptr;
  double* sh = nullptr;
  if (residual != nullptr) {
    residuals_.Resize(static_cast<size_t>(m) * kResidualDim);
    residual->Evaluate(residual_params, m, dynamic.x0, dynamic.cycle_index,
                       dynamic.cycle_number, residuals_.data(),
                       &residual_ws_);
    has_residuals_ = true;
    opacity_logits_.Resize(count);
    CopyDoublesKernel(count, canonical.opacity_logits, opacity_logits_.data());
    const long long sh_size = 3LL * coeffs * count;
    sh_.Resize(sh_size);
    CopyDoublesKernel(sh_size, canonical.sh, sh_.data());
    opacity_logits = opacity_logits_.data();
    sh = sh_.data();
    view_.opacity_logits = opacity_logits;
    view_.sh = sh;
  }
  ComposeDynamicKernel(m, dynamic.index, dynamic.positions, residuals(),
                       kResidualLayout, coeffs,
                       OffsetShCoeffs(kResidualLayout, coeffs), means_.data(),
                       opacity_logits, sh);
  return view_;
}

}  // namespace cuda
}  // namespace es
