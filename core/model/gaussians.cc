#include "core/model/gaussians.h"

#include <glog/logging.h>

namespace es {

void GaussianSet::Resize(int n) {
  const int old = size();
  for (const GaussianArray& a : kGaussianArrays) {
    std::vector<double>& v = this->*a.values;
    const size_t width = a.Width(sh_coeffs());
    v.resize(width * n, 0.0);
    for (int i = old; i < n; ++i) v[width * i] = a.first_value;
  }
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
  for (const GaussianArray& a : kGaussianArrays) {
    const std::vector<double>& src = other.*a.values;
    const size_t width = a.Width(sh_coeffs());
    (this->*a.values)
        .insert((this->*a.values).end(), src.begin() + index * width,
                src.begin() + (index + 1) * width);
  }
}

void GaussianSet::Filter(const std::vector<bool>& keep) {
  CHECK_EQ(static_cast<int>(keep.size()), size());
  for (const GaussianArray& a : kGaussianArrays) {
    std::vector<double>& v = this->*a.values;
    const size_t width = a.Width(sh_coeffs());
    size_t out = 0;
    for (size_t i = 0; i < keep.size(); ++i) {
      if (!keep[i]) continue;
      for (size_t j = 0; j < width; ++j) v[out * width + j] = v[i * width + j];
      ++out;
    }
    v.resize(out * width);
  }
}

void GaussianSet::CheckConsistent() const {
  const size_t n = size();
  CHECK(sh_degree >= 0 && sh_degree <= kMaxShDegree);
  for (const GaussianArray& a : kGaussianArrays)
    CHECK_EQ((this->*a.values).size(), a.Width(sh_coeffs()) * n) << a.name;
}

}  // namespace es
