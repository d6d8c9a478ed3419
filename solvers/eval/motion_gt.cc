#include "solvers/eval/motion_gt.h"

#include <filesystem>
#include <memory>

#include <glog/logging.h>

#include "core/io/velocity_grid.h"

namespace es {
namespace {

std::string GridPath(const std::string& scene_dir) {
  return (std::filesystem::path(scene_dir) / "gt" / "velocity_grid.bin")
      .string();
}

// Mean endpoint error of `velocities` against the truth at `points`.
MotionGtMetrics Compare(const std::vector<Eigen::Vector3d>& points,
                        const std::vector<Eigen::Vector3d>& velocities,
                        const VelocityFunction& truth) {
  MotionGtMetrics m;
  m.num_points = static_cast<int>(points.size());
  if (points.empty()) return m;
  double error = 0, speed = 0, model_speed = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d gt = truth(points[i]);
    error += (velocities[i] - gt).norm();
    speed += gt.norm();
    model_speed += velocities[i].norm();
  }
  m.epe = error / points.size();
  m.mean_speed = speed / points.size();
  m.rel_epe = m.mean_speed > 0 ? m.epe / m.mean_speed : 0.0;
  m.speed_ratio = speed > 0 ? model_speed / speed : 0.0;
  return m;
}

}  // namespace

MotionGtMetrics EvaluateMotionGt(const MotionField& field,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const VelocityFunction& truth) {
  if (points.empty()) return {};
  std::vector<double> x(3 * points.size()), v(3 * points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    for (int c = 0; c < 3; ++c) x[3 * i + c] = points[i][c];
  }
  FieldWorkspace workspace;
  field.Evaluate(field.params(), static_cast<int>(points.size()), x.data(),
                 v.data(), &workspace);
  std::vector<Eigen::Vector3d> velocities(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    velocities[i] = Eigen::Map<const Eigen::Vector3d>(&v[3 * i]);
  }
  return Compare(points, velocities, truth);
}

MotionGtMetrics EvaluateSamplesGt(const std::vector<SceneFlowSample>& samples,
                                  const VelocityFunction& truth) {
  std::vector<Eigen::Vector3d> points, velocities;
  for (const SceneFlowSample& s : samples) {
    points.push_back(s.x);
    velocities.push_back(s.v);
  }
  return Compare(points, velocities, truth);
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
