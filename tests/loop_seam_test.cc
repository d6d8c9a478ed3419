#include "core/metrics/loop_seam.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace es {
namespace {

constexpr int kL = 8;

// Frame k of a smooth periodic animation: every pixel oscillates with
// period L at its own random phase, like water whose Gaussians loop with
// staggered start times.
std::vector<cv::Mat> PeriodicSequence(int frames, int first_frame) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> phase(0, 2 * M_PI);
  cv::Mat phases(32, 40, CV_64FC3);
  for (auto it = phases.begin<cv::Vec3d>(); it != phases.end<cv::Vec3d>();
       ++it) {
    *it = cv::Vec3d(phase(rng), phase(rng), phase(rng));
  }
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k) {
    cv::Mat f(phases.size(), CV_32FC3);
    const double t = 2 * M_PI * (first_frame + k) / kL;
    for (int i = 0; i < f.rows; ++i) {
      for (int j = 0; j < f.cols; ++j) {
        for (int c = 0; c < 3; ++c) {
          f.at<cv::Vec3f>(i, j)[c] = static_cast<float>(
              0.5 + 0.4 * std::sin(t + phases.at<cv::Vec3d>(i, j)[c]));
        }
      }
    }
    out.push_back(f);
  }
  return out;
}

// Every pixel ramps up over a cycle and snaps back at the boundary: what
// a loop without staggered start times looks like.
std::vector<cv::Mat> SawtoothSequence(int frames) {
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k) {
    out.push_back(cv::Mat(16, 16, CV_8UC3,
                          cv::Scalar::all(20 + 20 * (k % kL))));
  }
  return out;
}

TEST(LoopSeamTest, PeriodicSequenceScoresAboutOne) {
  for (int first : {0, 5}) {
    const LoopSeamScore s =
        ComputeLoopSeam(PeriodicSequence(3 * kL + 1, first), kL, first);
    EXPECT_EQ(s.boundary_pairs, 3);
    EXPECT_EQ(s.within_pairs, 3 * kL - 3);
    EXPECT_GT(s.within_change, 0.0);
    EXPECT_NEAR(s.score, 1.0, 0.05) << "first frame " << first;
  }
}

TEST(LoopSeamTest, JumpAtLoopBoundaryScoresHigh) {
  const LoopSeamScore s = ComputeLoopSeam(SawtoothSequence(3 * kL + 1), kL);
  EXPECT_EQ(s.boundary_pairs, 3);
  EXPECT_NEAR(s.within_change, 20.0, 1e-9);
  EXPECT_NEAR(s.boundary_change, 20.0 * (kL - 1), 1e-9);
  EXPECT_NEAR(s.score, kL - 1, 1e-9);
  // The same jump placed one frame later is not at the boundary the
  // caller declares, so the score drops below one.
  const LoopSeamScore shifted =
      ComputeLoopSeam(SawtoothSequence(3 * kL + 1), kL, 1);
  EXPECT_LT(shifted.score, 1.0);
}

TEST(LoopSeamTest, MaskRestrictsThePixelsCompared) {
  std::vector<cv::Mat> frames = SawtoothSequence(2 * kL + 1);
  // Outside the mask the pixels change smoothly every frame, boundary
  // included; the masked score sees only the sawtooth.
  cv::Mat mask(16, 16, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(0, 0, 8, 16)).setTo(255);
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k](cv::Rect(8, 0, 8, 16)).setTo(cv::Scalar::all(k * 10));
  }
  const LoopSeamScore full = ComputeLoopSeam(frames, kL);
  const LoopSeamScore masked = ComputeLoopSeam(frames, kL, 0, mask);
  EXPECT_NEAR(masked.score, kL - 1, 1e-9);
  EXPECT_LT(full.score, masked.score);
}

TEST(LoopSeamTest, TooShortOrStillSequences) {
  EXPECT_TRUE(std::isnan(ComputeLoopSeam(SawtoothSequence(kL), kL).score));
  std::vector<cv::Mat> still(2 * kL + 1, cv::Mat(4, 4, CV_32FC1, 0.5f));
  EXPECT_EQ(ComputeLoopSeam(still, kL).score, 1.0);
}

}  // namespace
}  // namespace es
