#ifndef EULERSPLAT_CORE_MASKS_COLOUR_MODEL_H_
#define EULERSPLAT_CORE_MASKS_COLOUR_MODEL_H_

#include <vector>

#include <opencv2/core.hpp>

namespace es {

// Which colours are water in this video: histograms of the colours inside
// the water regions and of those well outside them (the scenery), learned
// from the frames themselves. Water has colours of its own (white foam, a
// blue pool) that the scenery around it rarely shows.
class WaterColourModel {
 public:
  // frames: CV_32FC3 in [0, 1]; regions: CV_8UC1, 255 = water, a generous
  // region per frame. Pixels more than `inner` pixels inside a region teach
  // the water's colours, those more than `outer` pixels outside it the
  // scenery's. The water's colours are learned twice: the second time only
  // from the pixels the first model calls water (a region also holds the
  // scenery seen between droplets).
  WaterColourModel(const std::vector<cv::Mat>& frames,
                   const std::vector<cv::Mat>& regions, int inner, int outer);

  // log p(colour | water) - log p(colour | scenery).
  float LogRatio(const cv::Vec3f& colour) const;
  // LogRatio per pixel of a CV_32FC3 image: CV_32FC1.
  cv::Mat LogRatio(const cv::Mat& image) const;

  // A few typical water colours (k-means of the region's most water-like
  // colours): a spray's white and a pool's blue are both water.
  const std::vector<cv::Vec3f>& palette() const { return palette_; }
  // The mean of those colours: the water's side of colour space.
  const cv::Vec3f& mean_water() const { return mean_water_; }

 private:
  static constexpr int kBins = 16;  // per channel: ~0.06 wide
  static int Bin(const cv::Vec3f& colour);
  std::vector<float> log_ratio_;  // kBins^3
  std::vector<cv::Vec3f> palette_;
  cv::Vec3f mean_water_{1.f, 1.f, 1.f};
};

}  // namespace es

#endif  // EULERSPLAT_CORE_MASKS_COLOUR_MODEL_H_
