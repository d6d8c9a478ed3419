#include "core/io/velocity_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <glog/logging.h>

#include "core/base/input_error.h"

namespace es {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'V', 'G', 'R', 'I', 'D', '1'};
// Guards against allocating absurd sizes from a corrupt header.
constexpr int64_t kMaxNodes = int64_t{1} << 28;

int64_t NodeCount(const Eigen::Vector3i& r) {
  return int64_t{r.x()} * r.y() * r.z();
}

}  // namespace

Eigen::Vector3d VelocityGrid::Node(int i, int j, int k) const {
  const Eigen::Vector3d t(static_cast<double>(i) / (resolution.x() - 1),
                          static_cast<double>(j) / (resolution.y() - 1),
                          static_cast<double>(k) / (resolution.z() - 1));
  return box.min() + t.cwiseProduct(box.sizes());
}

Eigen::Vector3d VelocityGrid::At(int i, int j, int k) const {
  const size_t index =
      ((static_cast<size_t>(k) * resolution.y() + j) * resolution.x() + i) * 3;
  return {values[index], values[index + 1], values[index + 2]};
}

Eigen::Vector3d VelocityGrid::Sample(const Eigen::Vector3d& x) const {
  int lo[3];
  double w[3];
  for (int a = 0; a < 3; ++a) {
    const double extent = box.max()[a] - box.min()[a];
    const double u = std::clamp((x[a] - box.min()[a]) / extent, 0.0, 1.0) *
                     (resolution[a] - 1);
    lo[a] = std::min(static_cast<int>(u), resolution[a] - 2);
    w[a] = u - lo[a];
  }
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const double weight = (di ? w[0] : 1 - w[0]) * (dj ? w[1] : 1 - w[1]) *
                          (dk ? w[2] : 1 - w[2]);
    v += weight * At(lo[0] + di, lo[1] + dj, lo[2] + dk);
  }
  return v;
}

void WriteVelocityGrid(const VelocityGrid& grid, const std::string& path) {
  CHECK_EQ(static_cast<int64_t>(grid.values.size()),
           NodeCount(grid.resolution) * 3);
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path + ": cannot open for writing");
  out.write(kMagic, sizeof(kMagic));
  const int32_t res[3] = {grid.resolution.x(), grid.resolution.y(),
                          grid.resolution.z()};
  out.write(reinterpret_cast<const char*>(res), sizeof(res));
  const double box[6] = {grid.box.min().x(), grid.box.min().y(),
                         grid.box.min().z(), grid.box.max().x(),
                         grid.box.max().y(), grid.box.max().z()};
  out.write(reinterpret_cast<const char*>(box), sizeof(box));
  out.write(reinterpret_cast<const char*>(grid.values.data()),
            grid.values.size() * sizeof(float));
  if (!out) throw InputError(path + ": write failed");
}

VelocityGrid ReadVelocityGrid(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  char magic[8];
  int32_t res[3];
  double box[6];
  in.read(magic, sizeof(magic));
  if (!in || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw InputError(path + ": not a velocity grid (bad magic)");
  in.read(reinterpret_cast<char*>(res), sizeof(res));
  in.read(reinterpret_cast<char*>(box), sizeof(box));
  if (!in) throw InputError(path + ": truncated header");
  VelocityGrid grid;
  grid.resolution = {res[0], res[1], res[2]};
  if (grid.resolution.minCoeff() < 2 ||
      NodeCount(grid.resolution) > kMaxNodes)
    throw InputError(path + ": bad grid resolution");
  grid.box = Eigen::AlignedBox3d(Eigen::Vector3d(box[0], box[1], box[2]),
                                 Eigen::Vector3d(box[3], box[4], box[5]));
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box[a]) || !std::isfinite(box[a + 3]) ||
        !(box[a + 3] > box[a]))
      throw InputError(path + ": bad grid box");
  }
  grid.values.resize(NodeCount(grid.resolution) * 3);
  in.read(reinterpret_cast<char*>(grid.values.data()),
          grid.values.size() * sizeof(float));
  if (!in) throw InputError(path + ": truncated velocity values");
  for (float v : grid.values) {
    if (!std::isfinite(v)) throw InputError(path + ": NaN/Inf velocity");
  }
  return grid;
}

}  // namespace es
