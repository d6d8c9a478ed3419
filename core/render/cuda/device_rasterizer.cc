#include "core/render/cuda/device_rasterizer.h"

#include <glog/logging.h>

#include "core/model/gaussians.h"
#include "core/base/cuda/device_buffer.h"
#include "core/render/cuda/raster_kernels.h"

namespace es {
namespace cuda {
namespace {

// A host array as float on the device (nullptr stays nullptr).
const float* UploadAsFloat(const double* host, size_t size,
                           DeviceBuffer<float>* device) {
  if (host == nullptr) return nullptr;
  device->Upload(std::vector<float>(host, host + size));
  return device->data();
}

// A device float array as doubles on the host.
void DownloadAsDouble(const DeviceBuffer<float>& device,
                      std::vector<double>* host) {
  const std::vector<float> values = device.Download();
  host->assign(values.begin(), values.end());
}

}  // namespace

struct DeviceRasterizer::State {
  bool has_forward = false;
  bool has_backward = false;
  ProjectionInput input;  // camera, with the device splat pointers
  float background[3] = {0, 0, 0};
  DeviceSplatView splats;
  int num_visible = 0;
  int num_entries = 0;

  // Per Gaussian.
  DeviceBuffer<ProjectedGaussian> projected;
  DeviceBuffer<float> features;
  DeviceBuffer<int> tiles;
  DeviceBuffer<int> visible;  // one counter
  // Binning.
  BinScratch bin;
  DeviceBuffer<int> gaussians;  // per entry, by tile and depth
  DeviceBuffer<int> ranges;     // per tile: first and end entry
  // Per pixel.
  DeviceBuffer<float> rgb, alpha, depth, extra, t_final;
  DeviceBuffer<int> last;
  DeviceImages images;
  // Backward.
  DeviceBuffer<double> grad2d;

  // Copies of host inputs and outputs (the host interface).
  DeviceSplats host_splats;
  DeviceBuffer<float> d_rgb, d_alpha, d_depth, d_extra;
  DeviceGradientArrays host_grads;

  TileArgs MakeTileArgs() {
    TileArgs a;
    a.width = input.width;
    a.height = input.height;
    a.tiles_x = input.tiles_x;
    a.tiles_y = input.tiles_y;
    a.num_extra = splats.num_extra;
    for (int c = 0; c < 3; ++c) a.background[c] = background[c];
    a.ranges = ranges.data();
    a.gaussians = gaussians.data();
    a.projected = projected.data();
    a.features = features.data();
    a.t_final = t_final.data();
    a.last = last.data();
    return a;
  }
};

DeviceRasterizer::DeviceRasterizer() : state_(new State) {}
DeviceRasterizer::~DeviceRasterizer() = default;

const DeviceImages& DeviceRasterizer::ForwardDevice(
    const Camera& camera, const DeviceSplatView& splats,
    const Eigen::Vector3d& background) {
  CHECK(camera.width > 0 && camera.height > 0 && camera.fx > 0 &&
        camera.fy > 0)
      << "invalid camera " << camera.width << "x" << camera.height;
  CHECK(splats.sh_degree >= 0 && splats.sh_degree <= kMaxShDegree);
  CHECK(splats.num_extra >= 0 && splats.num_extra <= kMaxDeviceExtra)
      << "the device rasterizer renders at most " << kMaxDeviceExtra
      << " extra channels, not " << splats.num_extra;
  CHECK_GE(splats.count, 0);
  State& s = *state_;
  s.has_forward = false;
  s.has_backward = false;
  s.splats = splats;
  s.input = DeviceProjectionInput(camera, splats);
  for (int c = 0; c < 3; ++c)
    s.background[c] = static_cast<float>(background[c]);

  const int n = splats.count;
  const int nf = 4 + splats.num_extra;
  s.projected.Resize(n);
  s.features.Resize(static_cast<size_t>(nf) * n);
  s.tiles.Resize(n);
  s.visible.Resize(1);
  ProjectForward(s.input, n, splats.num_extra, splats.extra,
                 s.projected.data(), s.features.data(), s.tiles.data(),
                 s.visible.data());
  CopyToHost(&s.num_visible, s.visible.data(), sizeof(int));

  const int num_tiles = s.input.tiles_x * s.input.tiles_y;
  s.ranges.Resize(2 * static_cast<size_t>(num_tiles));
  s.num_entries =
      BinGaussians(n, s.input.tiles_x, s.input.tiles_y, s.projected.data(),
                   s.tiles.data(), &s.bin, &s.gaussians, s.ranges.data());

  const size_t pixels = static_cast<size_t>(camera.width) * camera.height;
  s.rgb.Resize(3 * pixels);
  s.alpha.Resize(pixels);
  s.depth.Resize(pixels);
  s.extra.Resize(pixels * splats.num_extra);
  s.t_final.Resize(pixels);
  s.last.Resize(pixels);
  TileArgs a = s.MakeTileArgs();
  a.rgb = s.rgb.data();
  a.alpha = s.alpha.data();
  a.depth = s.depth.data();
  a.extra = s.extra.data();
  RasterizeForward(a);

  s.images.width = camera.width;
  s.images.height = camera.height;
  s.images.num_extra = splats.num_extra;
  s.images.rgb = s.rgb.data();
  s.images.alpha = s.alpha.data();
  s.images.depth = s.depth.data();
  s.images.extra = s.extra.data();
  s.has_forward = true;
  return s.images;
}

void DeviceRasterizer::BackwardDevice(const DeviceImageGradients& image_grads,
                                      const DeviceSplatGradients& grads) {
  State& s = *state_;
  CHECK(s.has_forward) << "Backward before Forward";
  const int n = s.splats.count;
  const int stride = kTileGradHead + 4 + s.splats.num_extra;
  s.grad2d.Resize(static_cast<size_t>(stride) * n);
  s.grad2d.Zero();
  TileArgs a = s.MakeTileArgs();
  a.d_rgb = image_grads.d_rgb;
  a.d_alpha = image_grads.d_alpha;
  a.d_depth = image_grads.d_depth;
  a.d_extra = image_grads.d_extra;
  a.grad2d = s.grad2d.data();
  RasterizeBackward(a);
  const ProjectionGradients out = {grads.means, grads.log_scales, grads.quats,
                                   grads.opacity_logits, grads.sh};
  ProjectBackward(s.input, n, s.splats.num_extra, s.tiles.data(),
                  s.grad2d.data(), out, grads.extra);
  s.has_backward = true;
}

void DeviceRasterizer::Forward(const Camera& camera, const SplatView& splats,
                               const RenderOptions& options,
                               RenderResult* result) {
  CHECK(splats.sh_degree >= 0 && splats.sh_degree <= kMaxShDegree);
  State& s = *state_;
  s.host_splats.Upload(splats);
  ForwardDevice(camera, s.host_splats.View(), options.background);
  result->width = camera.width;
  result->height = camera.height;
  DownloadAsDouble(s.rgb, &result->rgb);
  DownloadAsDouble(s.alpha, &result->alpha);
  DownloadAsDouble(s.depth, &result->depth);
  DownloadAsDouble(s.extra, &result->extra);
}

void DeviceRasterizer::Backward(const RenderGradients& image_grads,
                                SplatGradients* grads) {
  State& s = *state_;
  CHECK(s.has_forward) << "Backward before Forward";
  const size_t pixels = static_cast<size_t>(s.input.width) * s.input.height;
  const int num_extra = s.splats.num_extra;
  DeviceImageGradients ig;
  ig.d_rgb = UploadAsFloat(image_grads.d_rgb, 3 * pixels, &s.d_rgb);
  ig.d_alpha = UploadAsFloat(image_grads.d_alpha, pixels, &s.d_alpha);
  ig.d_depth = UploadAsFloat(image_grads.d_depth, pixels, &s.d_depth);
  ig.d_extra =
      UploadAsFloat(image_grads.d_extra, num_extra * pixels, &s.d_extra);
  s.host_grads.Resize(s.splats.count, s.splats.sh_degree, num_extra);
  BackwardDevice(ig, s.host_grads.View());
  s.host_grads.Download(grads);
}

int DeviceRasterizer::num_visible() const { return state_->num_visible; }
int DeviceRasterizer::num_entries() const { return state_->num_entries; }

void DeviceRasterizer::Radii(std::vector<int>* radii) const {
  const State& s = *state_;
  radii->assign(s.splats.count, 0);
  if (!s.has_forward) return;
  const std::vector<ProjectedGaussian> projected = s.projected.Download();
  for (int n = 0; n < s.splats.count; ++n) (*radii)[n] = projected[n].radius;
}

void DeviceRasterizer::Mean2dGradients(std::vector<double>* grads) const {
  const State& s = *state_;
  grads->assign(2 * static_cast<size_t>(s.splats.count), 0.0);
  if (!s.has_backward) return;  // no backward since the last forward
  const std::vector<double> grad2d = s.grad2d.Download();
  const std::vector<int> tiles = s.tiles.Download();
  const size_t stride = kTileGradHead + 4 + s.splats.num_extra;
  for (int n = 0; n < s.splats.count; ++n) {
    if (tiles[n] == 0) continue;
    (*grads)[2 * n] = grad2d[stride * n];
    (*grads)[2 * n + 1] = grad2d[stride * n + 1];
  }
}

void DeviceRasterizer::RadiiDevice(int* radii) const {
  const State& s = *state_;
  if (!s.has_forward) {
    DeviceZero(radii, sizeof(int) * s.splats.count);
    return;
  }
  CopyRadii(s.splats.count, s.projected.data(), radii);
}

void DeviceRasterizer::Mean2dGradientsDevice(double* grads) const {
  const State& s = *state_;
  if (!s.has_backward) {  // no backward since the last forward
    DeviceZero(grads, 2 * sizeof(double) * s.splats.count);
    return;
  }
  CopyMean2dGradients(s.splats.count, s.tiles.data(), s.grad2d.data(),
                      kTileGradHead + 4 + s.splats.num_extra, grads);
}

}  // namespace cuda
}  // namespace es
