#include "core/metrics/ssim.h"

#include <glog/logging.h>

namespace es {

template <typename T>
void ComputeSsimTarget(const cv::Mat& y, SsimScratch<T>* scratch,
                       SsimTarget<T>* target) {
  CHECK(y.depth() == CV_32F || y.depth() == CV_64F) << "SSIM target type";
  CHECK(y.isContinuous());
  if (y.depth() == cv::DataType<T>::depth) {
    ComputeSsimTarget(y.ptr<T>(), y.rows, y.cols, y.channels(), scratch,
                      target);
    return;
  }
  target->converted.resize(y.total() * y.channels());
  cv::Mat wrapped(y.rows, y.cols,
                  CV_MAKETYPE(cv::DataType<T>::depth, y.channels()),
                  target->converted.data());
  y.convertTo(wrapped, wrapped.type());
  ComputeSsimTarget(target->converted.data(), y.rows, y.cols, y.channels(),
                    scratch, target);
}

template void ComputeSsimTarget(const cv::Mat&, SsimScratch<float>*,
                                SsimTarget<float>*);
template void ComputeSsimTarget(const cv::Mat&, SsimScratch<double>*,
                                SsimTarget<double>*);

}  // namespace es
