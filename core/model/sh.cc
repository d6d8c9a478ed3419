#include "core/model/sh.h"

namespace es {
namespace {

constexpr double kC0 = 0.28209479177387814;
constexpr double kC1 = 0.4886025119029199;
constexpr double kC2[5] = {1.0925484305920792, -1.0925484305920792,
                           0.31539156525252005, -1.0925484305920792,
                           0.5462742152960396};
constexpr double kC3[7] = {-0.5900435899266435, 2.890611442640554,
                           -0.4570457994644658, 0.3731763325901154,
                           -0.4570457994644658, 1.445305721320277,
                           -0.5900435899266435};

}  // namespace

void EvalShBasis(int degree, const double dir[3], double* basis) {
  const double x = dir[0], y = dir[1], z = dir[2];
  basis[0] = kC0;
  if (degree < 1) return;
  basis[1] = -kC1 * y;
  basis[2] = kC1 * z;
  basis[3] = -kC1 * x;
  if (degree < 2) return;
  const double xx = x * x, yy = y * y, zz = z * z;
  basis[4] = kC2[0] * x * y;
  basis[5] = kC2[1] * y * z;
  basis[6] = kC2[2] * (2 * zz - xx - yy);
  basis[7] = kC2[3] * x * z;
  basis[8] = kC2[4] * (xx - yy);
  if (degree < 3) return;
  basis[9] = kC3[0] * y * (3 * xx - yy);
  basis[10] = kC3[1] * x * y * z;
  basis[11] = kC3[2] * y * (4 * zz - xx - yy);
  basis[12] = kC3[3] * z * (2 * zz - 3 * xx - 3 * yy);
  basis[13] = kC3[4] * x * (4 * zz - xx - yy);
  basis[14] = kC3[5] * z * (xx - yy);
  basis[15] = kC3[6] * x * (xx - 3 * yy);
}

void ShBasisBackward(int degree, const double dir[3], const double* g,
                     double d_dir[3]) {
  const double x = dir[0], y = dir[1], z = dir[2];
  double dx = 0, dy = 0, dz = 0;
  if (degree >= 1) {
    dy += -kC1 * g[1];
    dz += kC1 * g[2];
    dx += -kC1 * g[3];
  }
  if (degree >= 2) {
    dx += kC2[0] * y * g[4];
    dy += kC2[0] * x * g[4];
    dy += kC2[1] * z * g[5];
    dz += kC2[1] * y * g[5];
    dx += -2 * kC2[2] * x * g[6];
    dy += -2 * kC2[2] * y * g[6];
    dz += 4 * kC2[2] * z * g[6];
    dx += kC2[3] * z * g[7];
    dz += kC2[3] * x * g[7];
    dx += 2 * kC2[4] * x * g[8];
    dy += -2 * kC2[4] * y * g[8];
  }
  if (degree >= 3) {
    const double xx = x * x, yy = y * y, zz = z * z;
    dx += kC3[0] * 6 * x * y * g[9];
    dy += kC3[0] * (3 * xx - 3 * yy) * g[9];
    dx += kC3[1] * y * z * g[10];
    dy += kC3[1] * x * z * g[10];
    dz += kC3[1] * x * y * g[10];
    dx += kC3[2] * (-2 * x * y) * g[11];
    dy += kC3[2] * (4 * zz - xx - 3 * yy) * g[11];
    dz += kC3[2] * 8 * y * z * g[11];
    dx += kC3[3] * (-6 * x * z) * g[12];
    dy += kC3[3] * (-6 * y * z) * g[12];
    dz += kC3[3] * (6 * zz - 3 * xx - 3 * yy) * g[12];
    dx += kC3[4] * (4 * zz - 3 * xx - yy) * g[13];
    dy += kC3[4] * (-2 * x * y) * g[13];
    dz += kC3[4] * 8 * x * z * g[13];
    dx += kC3[5] * 2 * x * z * g[14];
    dy += kC3[5] * (-2 * y * z) * g[14];
    dz += kC3[5] * (xx - yy) * g[14];
    dx += kC3[6] * (3 * xx - 3 * yy) * g[15];
    dy += kC3[6] * (-6 * x * y) * g[15];
  }
  d_dir[0] = dx;
  d_dir[1] = dy;
  d_dir[2] = dz;
}

}  // namespace es
