#include "solvers/poses/colmap_poses.h"

#include <stdlib.h>  // mkdtemp
#include <sys/resource.h>  // getrusage

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "solvers/poses/subprocess.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time (user + system) of the finished child processes so far.
double ChildCpuSeconds() {
  rusage usage;
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Wall and CPU time of one step.
struct StepTimer {
  Clock::time_point start = Clock::now();
  double cpu_start = ChildCpuSeconds();
  void Stop(double* wall, double* cpu) const {
    *wall = SecondsSince(start);
    *cpu = ChildCpuSeconds() - cpu_start;
  }
};

void WritePairList(const std::vector<std::string>& names, int overlap,
                   const fs::path& path) {
  std::ofstream out(path);
  for (const auto& [a, b] :
       VideoMatchPairs(static_cast<int>(names.size()), overlap))
    out << names[a] << ' ' << names[b] << '\n';
  if (!out) throw InputError(path.string() + ": cannot write");
}

bool IsImageFile(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

std::vector<std::string> ImageNames(const fs::path& images) {
  if (!fs::is_directory(images))
    throw InputError(images.string() + ": no such folder");
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(images))
    if (entry.is_regular_file() && IsImageFile(entry.path()))
      names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  if (names.size() < 2)
    throw InputError(images.string() + ": COLMAP needs at least 2 image "
                     "files (png/jpg); a video must be imported first "
                     "(eulersplat --video)");
  return names;
}

// A fresh folder under the system's temporary directory.
fs::path MakeWorkDir() {
  std::string pattern =
      (fs::temp_directory_path() / "es_poses_XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError(pattern + ": cannot create a temporary folder");
  return pattern;
}

// Writes the frames, scaled to the SfM width, into work/images; returns
// the full frame size and sets the scale factors.
cv::Size WriteSfmFrames(const fs::path& images,
                        const std::vector<std::string>& names,
                        int sfm_width, const fs::path& out, double* sx,
                        double* sy) {
  fs::create_directories(out);
  cv::Size full, small;
  for (const std::string& name : names) {
    const cv::Mat image = cv::imread((images / name).string());
    if (image.empty())
      throw InputError((images / name).string() + ": cannot decode image");
    if (full.area() == 0) {
      full = image.size();
      small = full;
      if (sfm_width > 0 && full.width > sfm_width)
        small = cv::Size(sfm_width,
                         std::max(1, static_cast<int>(std::lround(
                                         double(full.height) * sfm_width /
                                         full.width))));
    } else if (image.size() != full) {
      throw InputError((images / name).string() +
                       ": frames differ in size; one video has one size");
    }
    cv::Mat scaled = image;
    if (small != full) cv::resize(image, scaled, small, 0, 0, cv::INTER_AREA);
    // PNG whatever the source: COLMAP reads the names it is given.
    if (!cv::imwrite((out / name).string(), scaled))
      throw InputError((out / name).string() + ": cannot write");
  }
  *sx = double(small.width) / full.width;
  *sy = double(small.height) / full.height;
  return full;
}

void RunStep(const std::string& step, const std::vector<std::string>& argv,
             const fs::path& log) {
  const int status = RunLogged(argv, log.string());
  if (status == 127)
    throw InputError(argv[0] + ": cannot run COLMAP (install the colmap "
                     "package or give its binary)");
  if (status != 0)
    throw InputError("COLMAP " + step + " failed (exit status " +
                     std::to_string(status) + "); end of its log:\n" +
                     TailOfFile(log.string(), 15));
}

// The mapper's largest model (most registered images), or an empty one.
ColmapModel LargestModel(const fs::path& sparse, int* models) {
  ColmapModel best;
  *models = 0;
  if (!fs::is_directory(sparse)) return best;
  for (const fs::directory_entry& entry : fs::directory_iterator(sparse)) {
    if (!HasColmapBinary(entry.path().string())) continue;
    ++*models;
    ColmapModel model = ReadColmapBinary(entry.path().string());
    if (model.images.size() > best.images.size()) best = std::move(model);
  }
  return best;
}

}  // namespace

std::vector<std::pair<int, int>> VideoMatchPairs(int frames, int overlap) {
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < frames; ++i) {
    for (int d = 1; d <= overlap && i + d < frames; ++d)
      pairs.emplace_back(i, i + d);
    for (int d = 1; i + d < frames; d *= 2)
      if (d > overlap) pairs.emplace_back(i, i + d);
  }
  return pairs;
}

void RescaleColmapModel(double sx, double sy, int width, int height,
                        ColmapModel* model) {
  for (auto& [id, camera] : model->cameras) {
    std::vector<double>& p = camera.params;
    if (camera.model == "PINHOLE") {
      p[0] /= sx, p[1] /= sy, p[2] /= sx, p[3] /= sy;
    } else if (camera.model == "SIMPLE_PINHOLE" ||
               camera.model == "SIMPLE_RADIAL" || camera.model == "RADIAL") {
      // One focal length: the two factors differ by rounding only.
      p[0] /= 0.5 * (sx + sy), p[1] /= sx, p[2] /= sy;
    } else {
      throw InputError("camera model " + camera.model +
                       " cannot be rescaled; use PINHOLE or SIMPLE_RADIAL");
    }
    camera.width = width;
    camera.height = height;
  }
  for (auto& [id, image] : model->images)
    for (Eigen::Vector2d& x : image.points2d) x = {x.x() / sx, x.y() / sy};
  for (ColmapPoint3D& point : model->points) point.error /= 0.5 * (sx + sy);
}

double MeanReprojectionError(const ColmapModel& model) {
  double sum = 0;
  long count = 0;
  for (const ColmapPoint3D& point : model.points) {
    sum += point.error * point.track.size();
    count += point.track.size();
  }
  return count > 0 ? sum / count : 0.0;
}

nlohmann::ordered_json PoseReportJson(const PoseReport& r) {
  return {{"frames", r.frames},
          {"registered", r.registered},
          {"models", r.models},
          {"points", r.points},
          {"mean_reprojection_error_px", r.mean_reprojection_error_px},
          {"sfm_scale", r.scale},
          {"extract_seconds", r.extract_seconds},
          {"match_seconds", r.match_seconds},
          {"map_seconds", r.map_seconds},
          {"total_seconds", r.total_seconds},
          {"extract_cpu_seconds", r.extract_cpu_seconds},
          {"match_cpu_seconds", r.match_cpu_seconds},
          {"map_cpu_seconds", r.map_cpu_seconds}};
}

PoseReport RecoverPoses(
    const std::string& scene_dir, const std::string& out_dir,
    const PoseOptions& options,
    const std::function<void(const std::string&)>& progress) {
  auto say = [&progress](const std::string& line) {
    if (progress) progress(line);
  };
  if (options.camera_model != "SIMPLE_PINHOLE" &&
      options.camera_model != "PINHOLE" &&
      options.camera_model != "SIMPLE_RADIAL")
    throw InputError("camera model must be SIMPLE_PINHOLE, PINHOLE or "
                     "SIMPLE_RADIAL, got " + options.camera_model);
  if (options.max_features < 100 || options.overlap < 1)
    throw InputError("max_features must be >= 100 and overlap >= 1");
  if (options.global_ba_ratio < 1.01)
    throw InputError("global_ba_ratio must be >= 1.01");
  if (fs::exists(out_dir))
    throw InputError(out_dir + ": exists; poses are only written to a new "
                     "folder (never over a scene's model)");
  const Clock::time_point start = Clock::now();
  const fs::path images = fs::path(scene_dir) / "images";
  const std::vector<std::string> names = ImageNames(images);

  PoseReport report;
  report.frames = static_cast<int>(names.size());
  const fs::path work = MakeWorkDir();
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{work};
  double sx = 1, sy = 1;
  const cv::Size full = WriteSfmFrames(images, names, options.sfm_width,
                                       work / "images", &sx, &sy);
  report.scale = sx;
  const std::string db = (work / "database.db").string();
  const std::string threads = std::to_string(options.threads);
  setenv("QT_QPA_PLATFORM", "offscreen", 0);  // no display needed

  say("feature extraction: " + std::to_string(names.size()) + " frames at " +
      std::to_string(int(std::lround(full.width * sx))) + " px wide, at most " +
      std::to_string(options.max_features) + " features each");
  StepTimer timer;
  RunStep("feature extraction",
          {options.colmap, "feature_extractor", "--database_path", db,
           "--image_path", (work / "images").string(),
           "--ImageReader.single_camera", "1", "--ImageReader.camera_model",
           options.camera_model, "--SiftExtraction.use_gpu", "0",
           "--SiftExtraction.num_threads", threads,
           "--SiftExtraction.max_num_features",
           std::to_string(options.max_features),
           "--SiftExtraction.first_octave", options.upsample ? "-1" : "0"},
          work / "extract.log");
  timer.Stop(&report.extract_seconds, &report.extract_cpu_seconds);

  const fs::path pairs = work / "pairs.txt";
  WritePairList(names, options.overlap, pairs);
  say("matching each frame with the next " +
      std::to_string(options.overlap) + " and those 2^k after it");
  timer = StepTimer();
  RunStep("matching",
          {options.colmap, "matches_importer", "--database_path", db,
           "--match_list_path", pairs.string(), "--match_type", "pairs",
           "--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads",
           threads},
          work / "match.log");
  timer.Stop(&report.match_seconds, &report.match_cpu_seconds);

  say("incremental mapping");
  timer = StepTimer();
  fs::create_directories(work / "sparse");
  // Frames 2^k apart give the start the wide baseline (COLMAP's 16 degree
  // default, which it halves itself if no pair has it) that a short sweep
  // needs to pin down the focal length. Global bundle adjustment (COLMAP's
  // costliest step) each time the model grew by global_ba_ratio, once
  // rather than repeated until it settles; local adjustment after every
  // frame.
  const std::string ratio = std::to_string(options.global_ba_ratio);
  RunStep("mapping",
          {options.colmap, "mapper", "--database_path", db, "--image_path",
           (work / "images").string(), "--output_path",
           (work / "sparse").string(), "--Mapper.num_threads", threads,
           "--Mapper.ba_global_images_ratio", ratio,
           "--Mapper.ba_global_points_ratio", ratio,
           "--Mapper.ba_global_max_refinements", "1",
           "--Mapper.ba_global_max_num_iterations", "20",
           "--Mapper.ba_local_max_num_iterations", "15"},
          work / "map.log");
  timer.Stop(&report.map_seconds, &report.map_cpu_seconds);

  ColmapModel model = LargestModel(work / "sparse", &report.models);
  if (model.images.empty())
    throw InputError("COLMAP registered none of the " +
                     std::to_string(names.size()) + " frames of " +
                     images.string() + " (too little texture or motion?); "
                     "end of the mapper's log:\n" +
                     TailOfFile((work / "map.log").string(), 15));
  RescaleColmapModel(sx, sy, full.width, full.height, &model);
  report.registered = static_cast<int>(model.images.size());
  report.points = static_cast<int>(model.points.size());
  report.mean_reprojection_error_px = MeanReprojectionError(model);

  // Into a sibling first, so out_dir appears complete or not at all.
  const fs::path staging = fs::path(out_dir).string() + ".partial";
  fs::remove_all(staging);
  WriteColmapText(model, staging.string());
  fs::rename(staging, out_dir);
  report.total_seconds = SecondsSince(start);
  return report;
}

}  // namespace es
