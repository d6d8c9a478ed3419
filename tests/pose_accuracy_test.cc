// Pose accuracy after a similarity alignment: a model that differs from
// the truth only by scale, rotation and translation has no error (also
// when the camera path is a straight line), and a known extra error is
// measured as such.

#include "solvers/poses/pose_accuracy.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/base/input_error.h"

namespace es {
namespace {

// Cameras along a line (a sideways sweep), each turned a little.
ColmapModel LineOfCameras(int n) {
  ColmapModel model;
  for (int i = 0; i < n; ++i) {
    ColmapImage image;
    image.id = i + 1;
    image.name = "frame_" + std::to_string(i) + ".png";
    image.q_cw = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitY()) *
                 Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
    const Eigen::Vector3d centre(0.2 * i, 1.0, -3.0);
    image.t_cw = -(image.q_cw * centre);
    model.images[image.id] = image;
  }
  return model;
}

// The same world seen in coordinates x' = s R x + t.
ColmapModel Transformed(const ColmapModel& model, double s,
                        const Eigen::Quaterniond& r,
                        const Eigen::Vector3d& t) {
  ColmapModel out = model;
  for (auto& [id, image] : out.images) {
    const Eigen::Vector3d centre = -(image.q_cw.conjugate() * image.t_cw);
    image.q_cw = image.q_cw * r.conjugate();
    image.t_cw = -(image.q_cw * (s * (r * centre) + t));
  }
  return out;
}

TEST(PoseAccuracyTest, SimilarityIsNoError) {
  const ColmapModel truth = LineOfCameras(8);
  const Eigen::Quaterniond r(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const ColmapModel estimate =
      Transformed(truth, 0.37, r, Eigen::Vector3d(4, -1, 2));
  const PoseAccuracy a = ComparePoses(estimate, truth);
  EXPECT_EQ(a.compared, 8);
  EXPECT_NEAR(a.position_rmse, 0, 1e-9);
  EXPECT_NEAR(a.mean_rotation_error_deg, 0, 1e-6);
  EXPECT_NEAR(a.max_rotation_error_deg, 0, 1e-6);
}

// The estimate with frame 4 (the middle one) changed by `edit`.
template <typename Edit>
ColmapModel WithMiddleFrameEdited(const ColmapModel& truth, Edit edit) {
  ColmapModel estimate = Transformed(
      truth, 2.0, Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
  ColmapImage& image = estimate.images.at(5);
  Eigen::Vector3d centre = -(image.q_cw.conjugate() * image.t_cw);
  edit(&centre, &image.q_cw);
  image.t_cw = -(image.q_cw * centre);
  return estimate;
}

TEST(PoseAccuracyTest, MeasuresAKnownPositionError) {
  const ColmapModel truth = LineOfCameras(9);
  // Moved by 0.3 in the estimate's units (0.15 true) across the line.
  const ColmapModel estimate = WithMiddleFrameEdited(
      truth, [](Eigen::Vector3d* centre, Eigen::Quaterniond*) {
        centre->z() += 0.3;
      });
  const PoseAccuracy a = ComparePoses(estimate, truth);
  // The other frames pin the alignment: the error stays with frame 4,
  // less the shift the least-squares translation takes (1/9 of it).
  const double shift = 0.15;
  const double expected = std::sqrt(
      (std::pow(shift * 8 / 9, 2) + 8 * std::pow(shift / 9, 2)) / 9);
  EXPECT_NEAR(a.position_rmse, expected, 1e-3);
  EXPECT_NEAR(a.position_rmse_relative, expected / 0.8, 2e-3);
  EXPECT_NEAR(a.max_rotation_error_deg, 0, 1e-6);
}

TEST(PoseAccuracyTest, MeasuresAKnownRotationError) {
  const ColmapModel truth = LineOfCameras(9);
  // Turned by 2 degrees about its view axis.
  const ColmapModel estimate = WithMiddleFrameEdited(
      truth, [](Eigen::Vector3d*, Eigen::Quaterniond* q_cw) {
        *q_cw = Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                *q_cw;
      });
  const PoseAccuracy a = ComparePoses(estimate, truth);
  // The mean rotation takes 1/9 of the turn: frame 4 keeps 8/9 of it,
  // the others get 1/9.
  EXPECT_NEAR(a.max_rotation_error_deg, 2.0 * 8 / 9, 0.01);
  EXPECT_NEAR(a.mean_rotation_error_deg, (2.0 * 8 / 9 + 8 * 2.0 / 9) / 9,
              0.01);
}

TEST(PoseAccuracyTest, TooFewSharedFramesIsAnInputError) {
  const ColmapModel truth = LineOfCameras(5);
  ColmapModel other = LineOfCameras(2);
  EXPECT_THROW(ComparePoses(other, truth), InputError);
}

}  // namespace
}  // namespace es
