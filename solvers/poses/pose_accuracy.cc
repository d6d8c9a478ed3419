#include "solvers/poses/pose_accuracy.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "core/base/input_error.h"

namespace es {
namespace {

Eigen::Vector3d Centre(const ColmapImage& image) {
  return -(image.q_cw.conjugate() * image.t_cw);
}

}  // namespace

PoseAccuracy ComparePoses(const ColmapModel& estimate,
                          const ColmapModel& truth) {
  std::map<std::string, const ColmapImage*> true_by_name;
  for (const auto& [id, image] : truth.images)
    true_by_name[image.name] = &image;
  std::vector<const ColmapImage*> est, tru;
  for (const auto& [id, image] : estimate.images) {
    const auto it = true_by_name.find(image.name);
    if (it == true_by_name.end()) continue;
    est.push_back(&image);
    tru.push_back(it->second);
  }
  const int n = static_cast<int>(est.size());
  if (n < 3)
    throw InputError("pose comparison needs at least 3 frames in both "
                     "models, got " + std::to_string(n));
  // The rotation from the orientations (their chordal mean): a video's
  // camera path is often nearly a line, which leaves the rotation about it
  // undetermined by the centres alone.
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i)
    sum += tru[i]->q_cw.toRotationMatrix().transpose() *
           est[i]->q_cw.toRotationMatrix();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant();
  const Eigen::Matrix3d r = svd.matrixU() * flip * svd.matrixV().transpose();
  // Then scale and translation of the centres: true ~ s r est + t.
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (int i = 0; i < n; ++i) {
    from.col(i) = r * Centre(*est[i]);
    to.col(i) = Centre(*tru[i]);
  }
  const Eigen::Vector3d from_mean = from.rowwise().mean();
  const Eigen::Vector3d mean = to.rowwise().mean();
  const Eigen::Matrix3Xd from_c = from.colwise() - from_mean;
  const Eigen::Matrix3Xd to_c = to.colwise() - mean;
  const double spread = from_c.squaredNorm();
  const double s = spread > 0 ? (from_c.cwiseProduct(to_c)).sum() / spread
                              : 1.0;

  PoseAccuracy a;
  a.compared = n;
  double extent = 0, squared = 0, angles = 0;
  for (int i = 0; i < n; ++i) {
    extent = std::max(extent, to_c.col(i).norm());
    squared += (s * from_c.col(i) - to_c.col(i)).squaredNorm();
    // The estimate's world-to-camera rotation in the true world is
    // R_est r^T; its difference from the truth's is one angle.
    const Eigen::Matrix3d diff = est[i]->q_cw.toRotationMatrix() *
                                 r.transpose() *
                                 tru[i]->q_cw.toRotationMatrix().transpose();
    const double angle =
        Eigen::AngleAxisd(diff).angle() * 180.0 / M_PI;
    angles += angle;
    a.max_rotation_error_deg = std::max(a.max_rotation_error_deg, angle);
  }
  a.position_rmse = std::sqrt(squared / n);
  a.position_rmse_relative = extent > 0 ? a.position_rmse / extent : 0;
  a.mean_rotation_error_deg = angles / n;
  return a;
}

}  // namespace es
