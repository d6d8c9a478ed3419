#include "core/io/scene.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include <glog/logging.h>
#include <opencv2/imgproc.hpp>

#include "core/io/colmap_io.h"
#include "core/io/frame_loading.h"
#include "core/base/input_error.h"
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

// The COLMAP model of a scene and the file its cameras came from (for
// messages).
struct PosedModel {
  ColmapModel model;
  std::string cameras_file;
};

PosedModel ReadSceneModel(const fs::path& root) {
  const fs::path sparse = FindSparseDir(root);
  PosedModel out;
  out.model = ReadColmapModel(sparse.string());
  if (out.model.images.empty())
    throw InputError(sparse.string() + ": the COLMAP model has no images");
  out.cameras_file =
      (sparse /
       (HasColmapBinary(sparse.string()) ? "cameras.bin" : "cameras.txt"))
          .string();
  return out;
}

// The registered images in time order, which is name order.
std::vector<const ColmapImage*> ImagesInTimeOrder(const ColmapModel& model) {
  std::vector<const ColmapImage*> images;
  for (const auto& entry : model.images) images.push_back(&entry.second);
  std::sort(images.begin(), images.end(),
            [](const ColmapImage* a, const ColmapImage* b) {
              return a->name < b->name;
            });
  return images;
}

// One undistorter per camera, shared by its frames; *per_image points into
// *cameras for every image.
void MakeUndistorters(const PosedModel& posed,
                      const std::vector<const ColmapImage*>& images,
                      std::map<int, Undistorter>* cameras,
                      std::vector<const Undistorter*>* per_image) {
  for (const ColmapImage* image : images) {
    auto it = cameras->find(image->camera_id);
    if (it == cameras->end())
      it = cameras
               ->emplace(image->camera_id,
                         Undistorter(posed.model.cameras.at(image->camera_id),
                                     posed.cameras_file))
               .first;
    per_image->push_back(&it->second);
  }
}

// Reads, undistorts and scales every frame image; sets its camera.
void LoadImages(const fs::path& root, const std::string& cameras_file,
                const std::vector<const ColmapImage*>& images,
                const std::vector<std::string>& names,
                const std::vector<const Undistorter*>& undistorters,
                double image_scale, std::vector<Frame>* frames) {
  frames->resize(images.size());
  ForEachFrameImage(
      (root / "images").string(), names,
      [&](int i, const cv::Mat& raw, const std::string& source) {
        const ColmapImage& image = *images[i];
        const Undistorter& undistorter = *undistorters[i];
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
        Frame& frame = (*frames)[i];
        frame.camera = camera.Scaled(image_scale);
        if (frame.camera.width < 1 || frame.camera.height < 1)
          throw InputError(source + ": image scale " +
                           std::to_string(image_scale) +
                           " leaves less than one pixel");
        frame.image = ResizeTo(undistorter.Apply(ToRgbFloat(raw)),
                               frame.camera.width, frame.camera.height);
      });
}

FrameSplit LoadSplit(const fs::path& root,
                     const std::vector<std::string>& names,
                     const SceneOptions& options) {
  const fs::path split_file = root / "split.txt";
  if (fs::exists(split_file))
    return ReadSplitFile(split_file.string(), names);
  return DefaultSplit(names.size(), options.num_test_segments,
                      options.test_fraction);
}

}  // namespace

Scene LoadScene(const std::string& dir, const SceneOptions& options) {
  const fs::path root(dir);
  if (!fs::is_directory(root))
    throw InputError(dir + ": scene directory not found");
  if (!(options.image_scale > 0))
    throw InputError("image scale must be positive, got " +
                     std::to_string(options.image_scale));

  const PosedModel posed = ReadSceneModel(root);
  const std::vector<const ColmapImage*> images =
      ImagesInTimeOrder(posed.model);
  std::vector<std::string> names;
  for (const ColmapImage* image : images) names.push_back(image->name);
  std::map<int, Undistorter> cameras;
  std::vector<const Undistorter*> undistorters;
  MakeUndistorters(posed, images, &cameras, &undistorters);

  Scene scene;
  scene.dir = dir;
  const FrameSplit split = LoadSplit(root, names, options);
  scene.train = split.train;
  scene.test = split.test;
  LoadImages(root, posed.cameras_file, images, names, undistorters,
             options.image_scale, &scene.frames);
  const std::vector<int> times =
      FrameTimeIndices((root / "images").string(), names);
  for (size_t i = 0; i < times.size(); ++i)
    scene.frames[i].time_index = times[i];

  // Masks after images, so that missing images are reported first.
  const fs::path masks_dir = root / "masks";
  scene.has_masks = fs::is_directory(masks_dir);
  if (scene.has_masks)
    LoadMasks(masks_dir.string(), names, undistorters, &scene.frames);

  for (const ColmapPoint3D& point : posed.model.points) {
    scene.points.push_back(point.xyz);
    scene.point_colors.push_back(point.rgb.cast<double>() / 255.0);
  }
  LOG(INFO) << dir << ": " << scene.frames.size() << " frames ("
            << scene.train.size() << " train, " << scene.test.size()
            << " test), last at video frame "
            << (times.empty() ? 0 : times.back()) << ", "
            << scene.points.size() << " points";
  return scene;
}

}  // namespace es
