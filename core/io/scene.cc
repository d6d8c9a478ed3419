#include "core/io/scene.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/io/colmap_io.h"
#include "core/io/frame_loading.h"
#include "core/io/input_error.h"
#include "core/io/split.h"
#include "core/io/undistort.h"

namespace es {
namespace {

namespace fs = std::filesystem;

// sparse/0, or sparse/ itself when the model was written there directly.
fs::path FindSparseDir(const fs::path& root) {
  const fs::path sparse0 = root / "sparse" / "0";
  if (fs::is_directory(sparse0)) return sparse0;
  for (const char* file : {"cameras.bin", "cameras.txt"})
    if (fs::exists(root / "sparse" / file)) return root / "sparse";
  return sparse0;
}

cv::Mat ResizeTo(const cv::Mat& image, int width, int height) {
  if (image.cols == width && image.rows == height) return image;
  cv::Mat out;
  const bool shrink = width < image.cols;
  cv::resize(image, out, cv::Size(width, height), 0, 0,
             shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
  return out;
}

std::string SizeText(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// Reads the mask of every frame, undistorted and resized like its image.
void LoadMasks(const std::string& masks_dir,
               const std::vector<std::string>& names,
               const std::vector<const Undistorter*>& undistorters,
               std::vector<Frame>* frames) {
  const std::vector<std::string> files = FindMaskFiles(masks_dir, names);
  for (size_t i = 0; i < names.size(); ++i) {
    const Camera& source = undistorters[i]->pinhole();
    const cv::Mat mask = ReadMask(files[i]);
    if (mask.cols != source.width || mask.rows != source.height)
      throw InputError(files[i] + ": mask is " +
                       SizeText(mask.cols, mask.rows) + " but its image " +
                       names[i] + " is " +
                       SizeText(source.width, source.height));
    Frame& frame = (*frames)[i];
    frame.mask = ResizeTo(undistorters[i]->Apply(mask), frame.camera.width,
                          frame.camera.height);
  }
}

}  // namespace

Scene LoadScene(const std::string& dir, const SceneOptions& options) {
  const fs::path root(dir);
  if (!fs::is_directory(root))
    throw InputError(dir + ": scene directory not found");
  if (!(options.image_scale > 0))
    throw InputError("image scale must be positive, got " +
                     std::to_string(options.image_scale));

  const fs::path sparse = FindSparseDir(root);
  const ColmapModel model = ReadColmapModel(sparse.string());
  if (model.images.empty())
    throw InputError(sparse.string() + ": the COLMAP model has no images");
  const std::string cameras_file =
      (sparse /
       (HasColmapBinary(sparse.string()) ? "cameras.bin" : "cameras.txt"))
          .string();

  // Frames in time order, which is name order.
  std::vector<const ColmapImage*> images;
  for (const auto& entry : model.images) images.push_back(&entry.second);
  std::sort(images.begin(), images.end(),
            [](const ColmapImage* a, const ColmapImage* b) {
              return a->name < b->name;
            });
  std::vector<std::string> names;
  for (const ColmapImage* image : images) names.push_back(image->name);

  // One undistorter per camera, shared by its frames.
  std::map<int, Undistorter> undistorters;
  std::vector<const Undistorter*> frame_undistorters;
  for (const ColmapImage* image : images) {
    auto it = undistorters.find(image->camera_id);
    if (it == undistorters.end())
      it = undistorters
               .emplace(image->camera_id,
                        Undistorter(model.cameras.at(image->camera_id),
                                    cameras_file))
               .first;
    frame_undistorters.push_back(&it->second);
  }

  Scene scene;
  scene.dir = dir;
  const fs::path split_file = root / "split.txt";
  const FrameSplit split =
      fs::exists(split_file)
          ? ReadSplitFile(split_file.string(), names)
          : DefaultSplit(names.size(), options.num_test_segments,
                         options.test_fraction);
  scene.train = split.train;
  scene.test = split.test;

  scene.frames.resize(images.size());
  ForEachFrameImage(
      (root / "images").string(), names,
      [&](int i, const cv::Mat& raw, const std::string& source) {
        const ColmapImage& image = *images[i];
        const Undistorter& undistorter = *frame_undistorters[i];
        Camera camera = undistorter.pinhole();
        if (raw.cols != camera.width || raw.rows != camera.height)
          throw InputError(
              source + ": image is " + SizeText(raw.cols, raw.rows) +
              " but camera " + std::to_string(image.camera_id) + " in " +
              cameras_file + " is " + SizeText(camera.width, camera.height));
        camera.q_cw = image.q_cw;
        camera.t_cw = image.t_cw;
        camera.image_name = image.name;
        camera.image_id = image.id;
        Frame& frame = scene.frames[i];
        frame.camera = camera.Scaled(options.image_scale);
        if (frame.camera.width < 1 || frame.camera.height < 1)
          throw InputError(source + ": image scale " +
                           std::to_string(options.image_scale) +
                           " leaves less than one pixel");
        frame.image = ResizeTo(undistorter.Apply(ToRgbFloat(raw)),
                               frame.camera.width, frame.camera.height);
      });

  // Masks after images, so that missing images are reported first.
  const fs::path masks_dir = root / "masks";
  scene.has_masks = fs::is_directory(masks_dir);
  if (scene.has_masks)
    LoadMasks(masks_dir.string(), names, frame_undistorters, &scene.frames);

  for (const ColmapPoint3D& point : model.points) {
    scene.points.push_back(point.xyz);
    scene.point_colors.push_back(point.rgb.cast<double>() / 255.0);
  }
  LOG(INFO) << dir << ": " << scene.frames.size() << " frames ("
            << scene.train.size() << " train, " << scene.test.size()
            << " test), " << scene.points.size() << " points";
  return scene;
}

}  // namespace es
