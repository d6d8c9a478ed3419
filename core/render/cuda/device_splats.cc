#include "core/render/cuda/device_splats.h"

#include "core/model/gaussians.h"
#include "core/render/raster_project.h"

namespace es {
namespace cuda {

ProjectionInput DeviceProjectionInput(const Camera& camera,
                                      const DeviceSplatView& splats) {
  return MakeProjectionInput(ProjectionCamera(camera), splats);
}

void DeviceSplats::Upload(const SplatView& s) {
  const size_t n = s.count;
  means_.Upload(s.means, 3 * n);
  log_scales_.Upload(s.log_scales, 3 * n);
  quats_.Upload(s.quats, 4 * n);
  opacity_logits_.Upload(s.opacity_logits, n);
  sh_.Upload(s.sh, 3 * NumShCoeffs(s.sh_degree) * n);
  extra_.Upload(s.extra, s.num_extra * n);
  view_.count = s.count;
  view_.sh_degree = s.sh_degree;
  view_.num_extra = s.num_extra;
}

DeviceSplatView DeviceSplats::View() const {
  DeviceSplatView v = view_;
  v.means = means_.data();
  v.log_scales = log_scales_.data();
  v.quats = quats_.data();
  v.opacity_logits = opacity_logits_.data();
  v.sh = sh_.data();
  v.extra = extra_.data();
  return v;
}

void DeviceGradientArrays::Resize(int count, int sh_degree, int num_extra) {
  const size_t n = count;
  means_.Resize(3 * n);
  log_scales_.Resize(3 * n);
  quats_.Resize(4 * n);
  opacity_logits_.Resize(n);
  sh_.Resize(3 * NumShCoeffs(sh_degree) * n);
  extra_.Resize(num_extra * n);
}

DeviceSplatGradients DeviceGradientArrays::View() {
  return {{means_.data(), log_scales_.data(), quats_.data(),
           opacity_logits_.data(), sh_.data()},
          extra_.data()};
}

void DeviceGradientArrays::Download(SplatGradients* grads) const {
  grads->means = means_.Download();
  grads->log_scales = log_scales_.Download();
  grads->quats = quats_.Download();
  grads->opacity_logits = opacity_logits_.Download();
  grads->sh = sh_.Download();
  grads->extra = extra_.Download();
}

}  // namespace cuda
}  // namespace es
