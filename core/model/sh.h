#ifndef EULERSPLAT_CORE_MODEL_SH_H_
#define EULERSPLAT_CORE_MODEL_SH_H_

namespace es {

// Real spherical harmonics up to degree 3 with the constants and sign
// conventions of 3DGS (so PLY files from other tools render the same).
// `dir` is a unit vector; `basis` receives NumShCoeffs(degree) values.
void EvalShBasis(int degree, const double dir[3], double* basis);

// Vector-Jacobian product of EvalShBasis: d_dir = (d basis / d dir)^T
// d_basis, treating dir's components as independent (the caller applies the
// normalization Jacobian).
void ShBasisBackward(int degree, const double dir[3], const double* d_basis,
                     double d_dir[3]);

}  // namespace es

#endif  // EULERSPLAT_CORE_MODEL_SH_H_
