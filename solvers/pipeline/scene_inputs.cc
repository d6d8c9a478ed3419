#include "solvers/pipeline/scene_inputs.h"

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {
namespace {

namespace fs = std::filesystem;

bool IsVideoFile(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(c));
  for (const char* video : {".mp4", ".avi", ".mov", ".mkv", ".webm", ".m4v"})
    if (ext == video) return true;
  return false;
}

// The one video in images/ when it holds no image files.
fs::path VideoInImages(const fs::path& scene) {
  const fs::path images = scene / "images";
  if (!fs::is_directory(images)) return {};
  fs::path video;
  for (const fs::directory_entry& e : fs::directory_iterator(images)) {
    const std::string ext = e.path().extension().string();
    if (IsVideoFile(e.path())) {
      video = e.path();
    } else if (e.is_regular_file() && !ext.empty() && ext != ".txt") {
      return {};  // image files: not a video scene
    }
  }
  return video;
}

bool HasPoses(const fs::path& scene) {
  for (const char* file : {"cameras.txt", "cameras.bin"})
    if (fs::exists(scene / "sparse" / "0" / file) ||
        fs::exists(scene / "sparse" / file))
      return true;
  return false;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool JsonTrue(const std::string& json, const std::string& key) {
  return std::regex_search(json,
                           std::regex("\"" + key + "\": *true"));
}

void Say(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

// Decodes the video into OUT/scene (skipped when import.json says it is
// done; a partial import is redone from scratch).
fs::path ImportStep(const fs::path& video, const fs::path& out,
                    VideoImportOptions options) {
  const fs::path scene = out / "scene";
  const fs::path marker = scene / "import.json";
  if (fs::exists(marker)) {
    Say("\n[video] skipped: " + scene.string() + " holds its frames "
        "(delete it to redo)");
    return scene;
  }
  fs::remove_all(scene);
  Say("\n[video] decoding " + video.string() + " into " +
      (scene / "images").string());
  const VideoImportResult r = ImportVideo(
      video.string(), scene.string(), options, [](int done, int total) {
        if (done % 20 != 0 && done != total) return;
        std::printf("[video] frame %d / %d\n", done, total);
        std::fflush(stdout);
      });
  char json[320];
  std::snprintf(json, sizeof(json),
                "{\n  \"video\": \"%s\",\n  \"video_fps\": %.3f,\n"
                "  \"video_frames_read\": %d,\n  \"step\": %d,\n"
                "  \"frames\": %d,\n  \"width\": %d,\n  \"height\": %d\n}\n",
                fs::path(video).filename().c_str(), r.video_fps,
                r.video_frames, r.step, r.frames, r.width, r.height);
  WriteTextFileAtomically(marker.string(), json);
  std::printf("[video] %d frames at %dx%d (every %d of %d read, %.3g fps "
              "video)\n",
              r.frames, r.width, r.height, r.step, r.video_frames,
              r.video_fps);
  return scene;
}

void Link(const fs::path& target, const fs::path& link) {
  if (fs::exists(fs::symlink_status(link))) return;
  fs::create_symlink(fs::absolute(target), link);
}

// OUT/scene: links to the scene's parts, so poses and masks made for this
// run never go into the user's folder.
fs::path ViewStep(const fs::path& source, const fs::path& out,
                  const std::string& masks_dir) {
  const fs::path view = out / "scene";
  fs::create_directories(view);
  Link(source / "images", view / "images");
  for (const char* part : {"split.txt", "gt"})
    if (fs::exists(source / part)) Link(source / part, view / part);
  if (HasPoses(source)) Link(source / "sparse", view / "sparse");
  if (!masks_dir.empty()) {
    if (!fs::is_directory(masks_dir))
      throw InputError("--masks: " + masks_dir + ": no such folder");
    Link(masks_dir, view / "masks");
  }
  return view;
}

void PoseStep(const fs::path& scene, const std::string& pose_script,
              const StageRunner& run) {
  if (HasPoses(scene)) return;
  Say("\n[poses] " + scene.string() + " has no sparse/0: recovering poses");
  if (pose_script.empty()) {
    run("[poses]", "es_poses", {"--scene", scene.string()});
  } else {
    if (!fs::exists(pose_script))
      throw InputError("--pose_script: " + pose_script + ": not found");
    run("[poses]", "/bin/bash", {pose_script, scene.string()});
  }
  if (!HasPoses(scene))
    throw InputError("[poses] " + pose_script + " wrote no model into " +
                     (scene / "sparse" / "0").string());
}

}  // namespace

fs::path PrepareFramesAndPoses(const PipelineOptions& request,
                               const StageRunner& run) {
  if (request.video.empty() == request.scene.empty())
    throw InputError("give exactly one of --video and --scene");
  const bool user_masks = !request.masks.empty() && request.masks != "auto" &&
                          request.masks != "none";
  fs::path scene;
  fs::path video = request.video;
  if (video.empty()) {
    if (!fs::is_directory(request.scene))
      throw InputError(request.scene + ": no such directory");
    const fs::path inside = VideoInImages(request.scene);
    // A video with poses is read as it is (LoadScene decodes its frames);
    // without, COLMAP needs image files.
    if (!inside.empty() && !HasPoses(request.scene)) video = inside;
  }
  if (!video.empty()) {
    VideoImportOptions options = request.import;
    if (user_masks) options.masks_dir = request.masks;
    else if (request.masks.empty() && request.video.empty() &&
             fs::is_directory(fs::path(request.scene) / "masks"))
      options.masks_dir = (fs::path(request.scene) / "masks").string();
    scene = ImportStep(video, request.out, options);
  } else {
    const fs::path source = request.scene;
    const bool keep_own_masks =
        request.masks.empty() && fs::is_directory(source / "masks");
    if (HasPoses(source) && keep_own_masks) {
      scene = source;  // nothing to add
    } else {
      const bool own_masks_as_given =
          keep_own_masks && !HasPoses(source);
      scene = ViewStep(source, request.out,
                       user_masks ? request.masks
                       : own_masks_as_given ? (source / "masks").string()
                                            : "");
    }
  }
  PoseStep(scene, request.pose_script, run);
  return scene;
}

PreparedScene PrepareMasks(const PipelineOptions& request,
                           const fs::path& scene, const MaskProbe& probe,
                           const StageRunner& run) {
  const fs::path run_dir = request.out;
  PreparedScene out;
  out.scene = scene;
  if (request.masks == "none") {
    out.static_only = true;
    out.why_static = "--masks none: everything is static";
    return out;
  }
  if (fs::is_directory(scene / "masks") && request.masks != "auto") {
    Say("\n[masks] using " + (scene / "masks").string());
    out.has_masks = true;
    return out;
  }
  const fs::path report = run_dir / "masks_report.json";
  if (!fs::exists(report)) {
    Say("\n[masks] no masks: finding the water from the video (a static "
        "fit without masks, then where it cannot explain the frames)");
    const fs::path probe_dir = run_dir / "mask_probe";
    if (!fs::exists(probe_dir / "static.ply")) {
      std::vector<std::string> args = {
          "--scene", scene.string(), "--out", probe_dir.string(),
          "--iterations", std::to_string(probe.iterations), "--mask_weight",
          "0"};
      args.insert(args.end(), probe.static_flags.begin(),
                  probe.static_flags.end());
      if (fs::exists(probe_dir / "checkpoint.bin")) args.push_back("--resume");
      run("[masks]", "es_static", args);
    }
    fs::remove_all(scene / "masks.partial");
    if (fs::is_symlink(scene / "masks") || fs::exists(scene / "masks"))
      throw InputError((scene / "masks").string() + ": exists but " +
                       report.string() + " does not; delete one to redo");
    std::vector<std::string> args = {
        "--scene", scene.string(), "--static",
        (probe_dir / "static.ply").string(), "--out",
        (scene / "masks").string(), "--sheet",
        (run_dir / "masks_sheet.png").string(), "--report",
        report.string()};
    // A scene that brought masks of its own but was asked for auto ones
    // (e.g. a synthetic one): its masks are the truth the report scores.
    const fs::path own_masks = fs::path(request.scene) / "masks";
    if (!request.scene.empty() && fs::is_directory(own_masks)) {
      args.push_back("--truth");
      args.push_back(own_masks.string());
    }
    args.insert(args.end(), probe.mask_flags.begin(), probe.mask_flags.end());
    run("[masks]", "es_masks", args);
  } else {
    Say("\n[masks] skipped: " + report.string() + " exists (delete it and " +
        (scene / "masks").string() + " to redo)");
  }
  out.has_masks = JsonTrue(ReadText(report), "has_water");
  if (!out.has_masks) {
    out.static_only = true;
    out.why_static =
        "no water found: nothing in the video moves beyond what the camera "
        "motion explains (see " + (run_dir / "masks_sheet.png").string() +
        ")";
  }
  return out;
}

}  // namespace es
