#include "solvers/eval/motion_gt.h"

#include <filesystem>
#include <memory>

#include <glog/logging.h>

#include "core/io/csv_table.h"
#include "core/io/velocity_grid.h"

namespace es {
namespace {

std::string GridPath(const std::string& scene_dir) {
  return (std::filesystem::path(scene_dir) / "gt" / "velocity_grid.bin")
      .string();
}

}  // namespace

std::vector<MotionGtPoint> MotionGtPoints(
    const MotionField& field, const std::vector<Eigen::Vector3d>& points,
    const VelocityFunction& truth) {
  if (points.empty()) return {};
  const int n = static_cast<int>(points.size());
  std::vector<double> x(3 * points.size()), v(3 * points.size());
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) x[3 * i + c] = points[i][c];
  }
  FieldWorkspace workspace;
  field.Evaluate(field.params(), n, x.data(), v.data(), &workspace);
  std::vector<MotionGtPoint> out(points.size());
  for (int i = 0; i < n; ++i) {
    out[i] = {points[i], Eigen::Map<const Eigen::Vector3d>(&v[3 * i]),
              truth(points[i])};
  }
  return out;
}

MotionGtMetrics SummarizeMotionGt(const std::vector<MotionGtPoint>& points) {
  MotionGtMetrics m;
  m.num_points = static_cast<int>(points.size());
  if (points.empty()) return m;
  double error = 0, speed = 0, model_speed = 0;
  for (const MotionGtPoint& p : points) {
    error += (p.model - p.truth).norm();
    speed += p.truth.norm();
    model_speed += p.model.norm();
  }
  m.epe = error / points.size();
  m.mean_speed = speed / points.size();
  m.rel_epe = m.mean_speed > 0 ? m.epe / m.mean_speed : 0.0;
  m.speed_ratio = speed > 0 ? model_speed / speed : 0.0;
  return m;
}

std::string MotionGtCsv(const std::vector<MotionGtPoint>& points) {
  CsvTable table;
  table.columns = {"x",        "y",        "z",       "model_vx",
                   "model_vy", "model_vz", "true_vx", "true_vy",
                   "true_vz"};
  for (const MotionGtPoint& p : points) {
    table.rows.push_back({p.x.x(), p.x.y(), p.x.z(), p.model.x(), p.model.y(),
                          p.model.z(), p.truth.x(), p.truth.y(),
                          p.truth.z()});
  }
  return CsvText(table);
}

MotionGtMetrics EvaluateMotionGt(const MotionField& field,
                                 const std::vector<Eigen::Vector3d>& points,
                                 const VelocityFunction& truth) {
  return SummarizeMotionGt(MotionGtPoints(field, points, truth));
}

MotionGtMetrics EvaluateSamplesGt(const std::vector<SceneFlowSample>& samples,
                                  const VelocityFunction& truth) {
  std::vector<MotionGtPoint> points;
  points.reserve(samples.size());
  for (const SceneFlowSample& s : samples) {
    points.push_back({s.x, s.v, truth(s.x)});
  }
  return SummarizeMotionGt(points);
}

void ReplaceWithTruth(const VelocityFunction& truth, TruthPart part,
                      std::vector<SceneFlowSample>* samples) {
  for (SceneFlowSample& s : *samples) {
    s.v = truth(s.x);
    if (part == TruthPart::kFull) {
      s.unseen.setZero();
    } else if (s.unseen.squaredNorm() > 0) {
      const Eigen::Vector3d line = s.unseen.normalized();
      s.v -= s.v.dot(line) * line;
    }
  }
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
