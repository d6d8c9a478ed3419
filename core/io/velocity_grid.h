#ifndef EULERSPLAT_CORE_IO_VELOCITY_GRID_H_
#define EULERSPLAT_CORE_IO_VELOCITY_GRID_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>


namespace es {

// Ground-truth velocity (world units per frame) sampled on the nodes of a
// regular grid over a box: node (i, j, k) sits at
//   box.min() + (i / (nx - 1), j / (ny - 1), k / (nz - 1)) * box.sizes().
//
// File gt/velocity_grid.bin, little-endian:
//   char[8]    "ESVGRID1"
//   int32[3]   nx, ny, nz            (each >= 2)
//   float64[3] box min (x, y, z)
//   float64[3] box max (x, y, z)
//   float32    nx*ny*nz*3 values: v = (vx, vy, vz) per node, x fastest,
//              then y, then z: index ((k * ny + j) * nx + i) * 3 + c
struct VelocityGrid {
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();
  Eigen::AlignedBox3d box;
  std::vector<float> values;

  Eigen::Vector3d Node(int i, int j, int k) const;
  Eigen::Vector3d At(int i, int j, int k) const;
  // Trilinear interpolation, clamped to the box.
  Eigen::Vector3d Sample(const Eigen::Vector3d& x) const;
};

// Throws InputError naming the file on an unreadable, truncated or
// malformed file.
void WriteVelocityGrid(const VelocityGrid& grid, const std::string& path);
VelocityGrid ReadVelocityGrid(const std::string& path);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_VELOCITY_GRID_H_
