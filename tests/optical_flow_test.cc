#include "core/flow/optical_flow.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"
#include "synth/random_texture.h"

namespace es {
namespace {

// Pixels at least `margin` from the border: the shift brings replicated
// border pixels in there.
cv::Mat Interior(cv::Size size, int margin) {
  cv::Mat valid(size, CV_8UC1, cv::Scalar(0));
  valid(cv::Rect(margin, margin, size.width - 2 * margin,
                 size.height - 2 * margin)) = 255;
  return valid;
}

double TranslationEpe(FlowMethod method, bool backward,
                      const cv::Mat& texture = TwoScaleTexture(160, 120, 3,
                                                               7)) {
  const cv::Vec2f shift(1.3f, -0.7f);
  const cv::Mat truth(texture.size(), CV_32FC2,
                      cv::Scalar(shift[0], shift[1]));
  const cv::Mat first = WarpByFlow(texture, truth);
  OpticalFlow flow(method);
  const FlowPair pair = flow.ComputePair(first, texture);
  const cv::Mat valid = Interior(texture.size(), 12);
  if (!backward) return MeanEndpointError(pair.forward, truth, valid);
  const cv::Mat back(texture.size(), CV_32FC2,
                     cv::Scalar(-shift[0], -shift[1]));
  return MeanEndpointError(pair.backward, back, valid);
}

TEST(OpticalFlowTest, DisRecoversSubpixelShift) {
  EXPECT_LT(TranslationEpe(FlowMethod::kDisMedium, false), 0.2);
  EXPECT_LT(TranslationEpe(FlowMethod::kDisMedium, true), 0.2);
}

// Texture of one or two pixels, like small water droplets: DIS's medium
// preset estimates at half resolution, where it is averaged away.
TEST(OpticalFlowTest, FineDisFollowsPixelSizedTexture) {
  cv::Mat noise(120, 160, CV_32FC3);
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 0.6);
  const double medium = TranslationEpe(FlowMethod::kDisMedium, false, noise);
  const double fine = TranslationEpe(FlowMethod::kDisFine, false, noise);
  EXPECT_LT(fine, 0.2);
  EXPECT_LT(fine, 0.5 * medium) << "medium " << medium << ", fine " << fine;
  EXPECT_LT(TranslationEpe(FlowMethod::kDisFine, true, noise), 0.2);
}

TEST(OpticalFlowTest, FarnebackRecoversSubpixelShift) {
  EXPECT_LT(TranslationEpe(FlowMethod::kFarneback, false), 0.2);
  EXPECT_LT(TranslationEpe(FlowMethod::kFarneback, true), 0.2);
}

TEST(OpticalFlowTest, ContribMethodRecoversShiftWhenAvailable) {
  for (FlowMethod m : AvailableFlowMethods()) {
    if (m != FlowMethod::kDualTvl1) continue;
    EXPECT_LT(TranslationEpe(m, false), 0.2);
  }
}

TEST(OpticalFlowTest, WarpByZeroFlowIsIdentity) {
  const cv::Mat texture = TwoScaleTexture(40, 30, 3, 3);
  const cv::Mat zero(texture.size(), CV_32FC2, cv::Scalar(0, 0));
  EXPECT_EQ(cv::norm(WarpByFlow(texture, zero), texture, cv::NORM_INF), 0.0);
}

TEST(OpticalFlowTest, WarpMovesContentAlongFlow) {
  cv::Mat image(20, 20, CV_32FC1, cv::Scalar(0));
  image.at<float>(10, 12) = 1.0f;
  const cv::Mat flow(image.size(), CV_32FC2, cv::Scalar(2, 0));
  // first(x) = second(x + f): the bright pixel appears 2 px to the left.
  EXPECT_EQ(WarpByFlow(image, flow).at<float>(10, 10), 1.0f);
}

TEST(OpticalFlowTest, EndpointErrorMeasuresDistance) {
  const cv::Mat a(4, 5, CV_32FC2, cv::Scalar(1, 1));
  const cv::Mat b(4, 5, CV_32FC2, cv::Scalar(4, 5));
  EXPECT_DOUBLE_EQ(MeanEndpointError(a, b), 5.0);
  cv::Mat valid(4, 5, CV_8UC1, cv::Scalar(0));
  EXPECT_DOUBLE_EQ(MeanEndpointError(a, b, valid), 0.0);
}

TEST(OpticalFlowTest, ParsesEveryAvailableNameAndRejectsOthers) {
  for (FlowMethod m : AvailableFlowMethods()) {
    EXPECT_EQ(ParseFlowMethod(FlowMethodName(m)), m);
  }
  EXPECT_THROW(ParseFlowMethod("lucas_kanade"), InputError);
}

TEST(OpticalFlowTest, GrayConversionScalesFloatToBytes) {
  const cv::Mat white(3, 3, CV_32FC3, cv::Scalar(1, 1, 1));
  const cv::Mat gray = ToGray8(white);
  EXPECT_EQ(gray.type(), CV_8UC1);
  EXPECT_EQ(gray.at<uint8_t>(1, 1), 255);
}

}  // namespace
}  // namespace es
