#include "solvers/motion_gt.h"

#include <filesystem>
#include <memory>

#include <glog/logging.h>

#include "core/synth_velocity_grid.h"

namespace es {
namespace {

std::string GridPath(const std::string& scene_dir) {
  return (std::filesystem::path(scene_dir) / "gt" / "velocity_grid.bin")
      .string();
}

}  // namespace

MotionGtMetrics EvaluateMotionGt(const MotionField& field,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const VelocityFunction& truth) {
  MotionGtMetrics m;
  m.num_points = static_cast<int>(points.size());
  if (points.empty()) return m;
  std::vector<double> x(3 * points.size()), v(3 * points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    for (int c = 0; c < 3; ++c) x[3 * i + c] = points[i][c];
  }
  FieldWorkspace workspace;
  field.Evaluate(field.params(), m.num_points, x.data(), v.data(), &workspace);
  double error = 0, speed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d gt = truth(points[i]);
    error += (Eigen::Map<const Eigen::Vector3d>(&v[3 * i]) - gt).norm();
    speed += gt.norm();
  }
  m.epe = error / points.size();
  m.mean_speed = speed / points.size();
  m.rel_epe = m.mean_speed > 0 ? m.epe / m.mean_speed : 0.0;
  return m;
}

bool HasMotionGt(const std::string& scene_dir) {
  return std::filesystem::exists(GridPath(scene_dir));
}

VelocityFunction LoadMotionGt(const std::string& scene_dir) {
  auto grid = std::make_shared<const VelocityGrid>(
      ReadVelocityGrid(GridPath(scene_dir)));
  return [grid](const Eigen::Vector3d& x) { return grid->Sample(x); };
}

}  // namespace es
