#include "core/model/gaussians.h"

#include <glog/logging.h>

namespace es {

void GaussianSet::Resize(int n) {
  const int old = size();
  means.resize(3 * n, 0.0);
  log_scales.resize(3 * n, 0.0);
  quats.resize(4 * n, 0.0);
  for (int i = old; i < n; ++i) quats[4 * i] = 1.0;
  opacity_logits.resize(n, 0.0);
  sh.resize(3 * sh_coeffs() * n, 0.0);
  dynamic_logits.resize(n, 0.0);
}

void GaussianSet::SetShDegree(int degree) {
  CHECK(degree >= 0 && degree <= kMaxShDegree) << "SH degree " << degree;
  const int n = size();
  const int k_old = sh_coeffs();
  const int k_new = NumShCoeffs(degree);
  std::vector<double> out(3 * k_new * n, 0.0);
  const int k_copy = std::min(k_old, k_new);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < k_copy; ++k)
      for (int c = 0; c < 3; ++c)
        out[(i * k_new + k) * 3 + c] = sh[(i * k_old + k) * 3 + c];
  sh.swap(out);
  sh_degree = degree;
}

void GaussianSet::AppendFrom(const GaussianSet& other, int index) {
  CHECK_EQ(other.sh_degree, sh_degree);
  const int k = sh_coeffs();
  auto append = [index](std::vector<double>& dst,
                        const std::vector<double>& src, int width) {
    dst.insert(dst.end(), src.begin() + index * width,
               src.begin() + (index + 1) * width);
  };
  append(means, other.means, 3);
  append(log_scales, other.log_scales, 3);
  append(quats, other.quats, 4);
  append(opacity_logits, other.opacity_logits, 1);
  append(sh, other.sh, 3 * k);
  append(dynamic_logits, other.dynamic_logits, 1);
}

void GaussianSet::Filter(const std::vector<bool>& keep) {
  CHECK_EQ(static_cast<int>(keep.size()), size());
  const int k = sh_coeffs();
  auto compact = [&keep](std::vector<double>& v, int width) {
    size_t out = 0;
    for (size_t i = 0; i < keep.size(); ++i) {
      if (!keep[i]) continue;
      for (int j = 0; j < width; ++j) v[out * width + j] = v[i * width + j];
      ++out;
    }
    v.resize(out * width);
  };
  compact(means, 3);
  compact(log_scales, 3);
  compact(quats, 4);
  compact(opacity_logits, 1);
  compact(sh, 3 * k);
  compact(dynamic_logits, 1);
}

void GaussianSet::CheckConsistent() const {
  const size_t n = size();
  CHECK(sh_degree >= 0 && sh_degree <= kMaxShDegree);
  CHECK_EQ(means.size(), 3 * n);
  CHECK_EQ(log_scales.size(), 3 * n);
  CHECK_EQ(quats.size(), 4 * n);
  CHECK_EQ(sh.size(), 3 * sh_coeffs() * n);
  CHECK_EQ(dynamic_logits.size(), n);
}

}  // namespace es
