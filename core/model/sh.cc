#include "core/model/sh.h"

#include "core/base/host_device.h"

namespace es {
namespace {

#include "core/model/sh_basis.inc"

}  // namespace

void EvalShBasis(int degree, const double dir[3], double* basis) {
  ShBasisAt(degree, dir[0], dir[1], dir[2], basis, 1);
}

void ShBasisBackward(int degree, const double dir[3], const double* g,
                     double d_dir[3]) {
  ShBasisBackwardAt(degree, dir[0], dir[1], dir[2], g, 1, d_dir);
}

}  // namespace es
