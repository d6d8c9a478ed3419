#ifndef EULERSPLAT_CORE_IO_VIDEO_IMPORT_H_
#define EULERSPLAT_CORE_IO_VIDEO_IMPORT_H_

#include <functional>
#include <string>

namespace es {

struct VideoImportOptions {
  // Frames per second kept; 0 keeps the video's own rate. Otherwise every
  // round(video fps / fps)-th frame is kept (never more than the video has).
  double fps = 0;
  // At most this many frames, the first ones of the video: the loop and the
  // motion field are per frame, so frames stay evenly spaced in time.
  int max_frames = 150;
  // Frames wider than this are scaled down (aspect kept); 0: never.
  int max_width = 640;
  // Optional masks of the video's frames, named like its frames
  // (frame_000000.png is the video's first frame, see VideoFrameName):
  // the chosen ones are resized and written beside the frames.
  std::string masks_dir;
};

struct VideoImportResult {
  double video_fps = 0;     // 0 when the container does not say
  int video_frames = 0;     // frames decoded
  int step = 1;             // every step-th frame kept
  int frames = 0;           // frames written
  int width = 0, height = 0;
};

// Decodes `video` and writes the chosen frames as scene_dir/images/
// frame_000000.png, ... (the names LoadScene and COLMAP read, numbered in
// the new time order) and, with masks_dir, scene_dir/masks/. Calls
// progress(frames written, frames expected) as it goes. Throws InputError
// naming the video (or mask) when it cannot be read, has no frames, or the
// options are invalid, and when scene_dir/images already holds files (it
// never mixes two imports or overwrites a scene).
VideoImportResult ImportVideo(
    const std::string& video, const std::string& scene_dir,
    const VideoImportOptions& options,
    const std::function<void(int, int)>& progress = nullptr);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_VIDEO_IMPORT_H_
