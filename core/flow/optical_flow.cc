#include "core/flow/optical_flow.h"

#include <cmath>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/base/input_error.h"

// The contrib methods need opencv_optflow, which CMake links when found.
#if __has_include(<opencv2/optflow.hpp>)
#include <opencv2/optflow.hpp>
#define ES_HAVE_OPTFLOW 1
#else
#define ES_HAVE_OPTFLOW 0
#endif

namespace es {
namespace {

constexpr FlowMethod kAllMethods[] = {
    FlowMethod::kDisUltrafast, FlowMethod::kDisFast,  FlowMethod::kDisMedium,
    FlowMethod::kDisFine,      FlowMethod::kFarneback, FlowMethod::kDeepFlow,
    FlowMethod::kDualTvl1,     FlowMethod::kPcaFlow};

bool IsContrib(FlowMethod method) {
  return method == FlowMethod::kDeepFlow || method == FlowMethod::kDualTvl1 ||
         method == FlowMethod::kPcaFlow;
}

cv::Ptr<cv::DenseOpticalFlow> CreateEstimator(FlowMethod method) {
  switch (method) {
    case FlowMethod::kDisUltrafast:
      return cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_ULTRAFAST);
    case FlowMethod::kDisFast:
      return cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
    case FlowMethod::kDisMedium:
      return cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
    case FlowMethod::kDisFine: {
      // The medium preset stops at half resolution; small videos' fine
      // water texture only shows at full resolution.
      cv::Ptr<cv::DISOpticalFlow> dis =
          cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
      dis->setFinestScale(0);
      return dis;
    }
    case FlowMethod::kFarneback:
      // A larger window than OpenCV's default (13) is steadier on the
      // low-texture water surfaces this is used on.
      return cv::FarnebackOpticalFlow::create(/*numLevels=*/5,
                                              /*pyrScale=*/0.5,
                                              /*fastPyramids=*/false,
                                              /*winSize=*/15,
                                              /*numIters=*/5, /*polyN=*/5,
                                              /*polySigma=*/1.1);
#if ES_HAVE_OPTFLOW
    case FlowMethod::kDeepFlow:
      return cv::optflow::createOptFlow_DeepFlow();
    case FlowMethod::kDualTvl1:
      return cv::optflow::createOptFlow_DualTVL1();
    case FlowMethod::kPcaFlow:
      return cv::optflow::createOptFlow_PCAFlow();
#else
    case FlowMethod::kDeepFlow:
    case FlowMethod::kDualTvl1:
    case FlowMethod::kPcaFlow:
      break;
#endif
  }
  LOG(FATAL) << "flow method " << FlowMethodName(method)
             << " is not available in this build";
  return nullptr;
}

}  // namespace

std::string FlowMethodName(FlowMethod method) {
  switch (method) {
    case FlowMethod::kDisUltrafast: return "dis_ultrafast";
    case FlowMethod::kDisFast: return "dis_fast";
    case FlowMethod::kDisMedium: return "dis";
    case FlowMethod::kDisFine: return "dis_fine";
    case FlowMethod::kFarneback: return "farneback";
    case FlowMethod::kDeepFlow: return "deepflow";
    case FlowMethod::kDualTvl1: return "tvl1";
    case FlowMethod::kPcaFlow: return "pcaflow";
  }
  return "unknown";
}

std::vector<FlowMethod> AvailableFlowMethods() {
  std::vector<FlowMethod> methods;
  for (FlowMethod m : kAllMethods) {
    if (ES_HAVE_OPTFLOW || !IsContrib(m)) methods.push_back(m);
  }
  return methods;
}

FlowMethod ParseFlowMethod(const std::string& name) {
  std::string names;
  for (FlowMethod m : AvailableFlowMethods()) {
    if (FlowMethodName(m) == name) return m;
    names += (names.empty() ? "" : ", ") + FlowMethodName(m);
  }
  throw InputError("unknown optical flow method '" + name +
                   "'; available: " + names);
}

cv::Mat ToGray8(const cv::Mat& image) {
  CHECK(!image.empty());
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_RGB2GRAY);
  } else {
    CHECK_EQ(image.channels(), 1);
    gray = image;
  }
  if (gray.depth() == CV_8U) return gray;
  cv::Mat gray8;
  gray.convertTo(gray8, CV_8U, gray.depth() == CV_32F ? 255.0 : 1.0);
  return gray8;
}

OpticalFlow::OpticalFlow(FlowMethod method)
    : method_(method), estimator_(CreateEstimator(method)) {}

cv::Mat OpticalFlow::ComputeGray(const cv::Mat& first, const cv::Mat& second) {
  CHECK_EQ(first.size(), second.size());
  cv::Mat flow(first.size(), CV_32FC2, cv::Scalar(0, 0));
  estimator_->calc(first, second, flow);
  CHECK_EQ(flow.type(), CV_32FC2);
  return flow;
}

cv::Mat OpticalFlow::Compute(const cv::Mat& first, const cv::Mat& second) {
  return ComputeGray(ToGray8(first), ToGray8(second));
}

FlowPair OpticalFlow::ComputePair(const cv::Mat& first, const cv::Mat& second) {
  const cv::Mat a = ToGray8(first), b = ToGray8(second);
  FlowPair pair;
  pair.forward = ComputeGray(a, b);
  pair.backward = ComputeGray(b, a);
  return pair;
}

cv::Mat WarpByFlow(const cv::Mat& image, const cv::Mat& flow) {
  CHECK_EQ(flow.type(), CV_32FC2);
  cv::Mat map(flow.size(), CV_32FC2);
  for (int y = 0; y < flow.rows; ++y) {
    const cv::Vec2f* f = flow.ptr<cv::Vec2f>(y);
    cv::Vec2f* m = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < flow.cols; ++x) m[x] = cv::Vec2f(x, y) + f[x];
  }
  cv::Mat warped;
  cv::remap(image, warped, map, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REPLICATE);
  return warped;
}

double MeanEndpointError(const cv::Mat& flow, const cv::Mat& reference,
                         const cv::Mat& valid) {
  CHECK_EQ(flow.type(), CV_32FC2);
  CHECK_EQ(reference.type(), CV_32FC2);
  CHECK_EQ(flow.size(), reference.size());
  CHECK(valid.empty() ||
        (valid.type() == CV_8UC1 && valid.size() == flow.size()));
  double sum = 0;
  long count = 0;
  for (int y = 0; y < flow.rows; ++y) {
    const cv::Vec2f* f = flow.ptr<cv::Vec2f>(y);
    const cv::Vec2f* r = reference.ptr<cv::Vec2f>(y);
    const uint8_t* v = valid.empty() ? nullptr : valid.ptr<uint8_t>(y);
    for (int x = 0; x < flow.cols; ++x) {
      if (v != nullptr && v[x] == 0) continue;
      sum += std::hypot(f[x][0] - r[x][0], f[x][1] - r[x][1]);
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace es
