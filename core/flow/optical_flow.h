#ifndef EULERSPLAT_CORE_FLOW_OPTICAL_FLOW_H_
#define EULERSPLAT_CORE_FLOW_OPTICAL_FLOW_H_

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

namespace es {

// Dense 2D optical flow between adjacent frames. A flow image is CV_32FC2,
// same size as the frames: flow(y, x) = (dx, dy) moves pixel (x, y) of the
// first frame onto its match at (x + dx, y + dy) in the second (OpenCV's
// convention; pixel centers as in docs/DESIGN.md, which a shift does not
// change).
enum class FlowMethod {
  kDisUltrafast,  // cv::DISOpticalFlow presets
  kDisFast,
  kDisMedium,
  kDisFine,       // the medium preset down to full resolution (finest scale 0)
  kFarneback,     // cv::calcOpticalFlowFarneback (pyramid 0.5, 5 levels)
  kDeepFlow,      // contrib cv::optflow (only if built with it)
  kDualTvl1,
  kPcaFlow,
};

// The flag spelling of each method: dis_ultrafast, dis_fast, dis (medium),
// dis_fine, farneback, deepflow, tvl1, pcaflow.
std::string FlowMethodName(FlowMethod method);
// The methods this build can run (contrib ones only with opencv_optflow).
std::vector<FlowMethod> AvailableFlowMethods();
// Parses a flag value; throws InputError listing the available names.
FlowMethod ParseFlowMethod(const std::string& name);

struct FlowPair {
  cv::Mat forward;   // first -> second
  cv::Mat backward;  // second -> first
};

// Converts a frame (CV_32FC3 RGB in [0, 1], CV_32FC1, or 8-bit) to the 8-bit
// gray image every method takes.
cv::Mat ToGray8(const cv::Mat& image);

// One estimator, reusable across frame pairs (DIS and the contrib methods
// keep internal buffers). Not thread-safe.
class OpticalFlow {
 public:
  explicit OpticalFlow(FlowMethod method);

  FlowMethod method() const { return method_; }
  // Flow from `first` to `second` (frames as accepted by ToGray8).
  cv::Mat Compute(const cv::Mat& first, const cv::Mat& second);
  // Both directions, for the forward-backward consistency check.
  FlowPair ComputePair(const cv::Mat& first, const cv::Mat& second);

 private:
  cv::Mat ComputeGray(const cv::Mat& first, const cv::Mat& second);

  FlowMethod method_;
  cv::Ptr<cv::DenseOpticalFlow> estimator_;
};

// Samples `image` at x + flow(x) (bilinear, border replicated): the second
// frame pulled back onto the first frame's grid. With a texture as `image`
// this also makes a first frame whose true forward flow is exactly `flow`.
cv::Mat WarpByFlow(const cv::Mat& image, const cv::Mat& flow);

// Mean endpoint error (px) between two flows over the pixels where `valid`
// (CV_8UC1, optional) is non-zero.
double MeanEndpointError(const cv::Mat& flow, const cv::Mat& reference,
                         const cv::Mat& valid = cv::Mat());

}  // namespace es

#endif  // EULERSPLAT_CORE_FLOW_OPTICAL_FLOW_H_
