#include "solvers/optim/adam.h"

#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/base/stage_profile.h"

namespace es {

namespace {

// Parameters per chunk of AdamUpdate's zero test.
constexpr int kAdamChunk = 64;

// Whether a[i], b[i] and c[i] are all zero (+0 or -0) for i < n: one
// branch-free pass over their bits, sign bits shifted out.
bool AllZero(const double* a, const double* b, const double* c, int n) {
  uint64_t bits = 0;
  for (int i = 0; i < n; ++i) {
    uint64_t x, y, z;
    std::memcpy(&x, a + i, sizeof(x));
    std::memcpy(&y, b + i, sizeof(y));
    std::memcpy(&z, c + i, sizeof(z));
    bits |= (x | y | z) << 1;
  }
  return bits == 0;
}

}  // namespace

AdamStep::AdamStep(const AdamOptions& o, int64_t t, double lr)
    : AdamConstants{o.beta1, o.beta2, o.eps, 0, 0} {
  CHECK_GE(t, 1);
  const double bc1 = 1.0 - std::pow(o.beta1, static_cast<double>(t));
  const double bc2 = 1.0 - std::pow(o.beta2, static_cast<double>(t));
  step = lr / bc1;
  inv_sqrt_bc2 = 1.0 / std::sqrt(bc2);
}

void AdamUpdate(const AdamOptions& o, int64_t t, double lr, int n,
                const double* grad, double* m, double* v, double* x) {
  // Per-Gaussian SH updates are timed by GaussianAdam::Step as a whole.
  ScopedStage timer(Stage::kAdam, n >= 1024);
  const AdamStep adam(o, t, lr);
  const int chunks = (n + kAdamChunk - 1) / kAdamChunk;
#pragma omp parallel for if (n > 65536) schedule(static)
  for (int c = 0; c < chunks; ++c) {
    const int begin = c * kAdamChunk;
    const int end = std::min(n, begin + kAdamChunk);
    // A zero gradient with zero moments leaves m, v and x exactly as they
    // are: such chunks (field texels no point has reached yet) are skipped.
    if (AllZero(grad + begin, m + begin, v + begin, end - begin)) continue;
    adam.Update(begin, end, grad, m, v, x);
  }
}

GaussianSet ZeroGaussians(int n, int sh_degree) {
  GaussianSet g;
  g.sh_degree = sh_degree;
  g.Resize(n);
  for (const GaussianArray& a : kGaussianArrays)
    std::fill((g.*a.values).begin(), (g.*a.values).end(), 0.0);
  return g;
}

void GaussianAdam::Reset(const GaussianSet& params) {
  m_ = ZeroGaussians(params.size(), params.sh_degree);
  v_ = m_;
  step_ = 0;
}

void GaussianAdam::Step(const GaussianLearningRates& lr,
                        const GaussianSet& grad, GaussianSet* params) {
  ScopedStage timer(Stage::kAdam);
  params->CheckConsistent();
  grad.CheckConsistent();
  CHECK_EQ(grad.size(), params->size());
  CHECK_EQ(grad.sh_degree, params->sh_degree);
  CHECK_EQ(m_.size(), params->size()) << "moments out of sync";
  CHECK_EQ(m_.sh_degree, params->sh_degree) << "moments out of sync";
  ++step_;
  for (int k = 0; k < kNumGaussianArrays; ++k) {
    if (k == kShArray) continue;  // below: two rates
    std::vector<double> GaussianSet::*const values = kGaussianArrays[k].values;
    std::vector<double>& x = params->*values;
    const double rate = lr.*kArrayLearningRates[k];
    if (rate == 0 || x.empty()) continue;
    AdamUpdate(options_, step_, rate, static_cast<int>(x.size()),
               (grad.*values).data(), (m_.*values).data(), (v_.*values).data(),
               x.data());
  }
  // SH: DC and the higher bands interleave per Gaussian ([n][k][rgb]).
  // The bias corrections once per step, not once per Gaussian.
  const int width = 3 * params->sh_coeffs();
  const int n = params->size();
  const AdamStep dc(options_, step_, lr.sh_dc);
  const AdamStep rest(options_, step_, lr.sh_rest);
  const double* g = grad.sh.data();
  double *m = m_.sh.data(), *v = v_.sh.data(), *x = params->sh.data();
#pragma omp parallel for if (n > 16384) schedule(static)
  for (int i = 0; i < n; ++i) {
    const int o = i * width;
    if (lr.sh_dc != 0) dc.Update(o, o + 3, g, m, v, x);
    if (width > 3 && lr.sh_rest != 0)
      rest.Update(o + 3, o + width, g, m, v, x);
  }
}

void GaussianAdam::Restore(const GaussianAdamState& state) {
  m_ = state.m;
  v_ = state.v;
  step_ = state.step;
}

void GaussianAdam::Filter(const std::vector<bool>& keep) {
  m_.Filter(keep);
  v_.Filter(keep);
}

void GaussianAdam::AppendZeros(int count) {
  const GaussianSet zeros = ZeroGaussians(count, m_.sh_degree);
  for (int i = 0; i < count; ++i) {
    m_.AppendFrom(zeros, i);
    v_.AppendFrom(zeros, i);
  }
}

void GaussianAdam::SetShDegree(int degree) {
  m_.SetShDegree(degree);
  v_.SetShDegree(degree);
}

void GaussianAdam::ResetOpacityMoments() {
  std::fill(m_.opacity_logits.begin(), m_.opacity_logits.end(), 0.0);
  std::fill(v_.opacity_logits.begin(), v_.opacity_logits.end(), 0.0);
}

}  // namespace es
