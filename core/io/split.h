#ifndef EULERSPLAT_CORE_IO_SPLIT_H_
#define EULERSPLAT_CORE_IO_SPLIT_H_

#include <string>
#include <vector>

namespace es {

// Which frames train and which are held out for evaluation; both are sorted
// frame indices and together cover every frame once.
struct FrameSplit {
  std::vector<int> train;
  std::vector<int> test;
};

// Holds out round(test_fraction * num_frames) frames (raised to one per
// segment when the video is long enough) as num_segments runs of consecutive
// frames spread evenly over the video, with training frames before the first
// run, between runs and after the last whenever there are enough frames.
// Throws InputError for a test_fraction outside [0, 1) or negative
// num_segments.
FrameSplit DefaultSplit(int num_frames, int num_segments, double test_fraction);

// Reads a split file (a scene's split.txt). Format: one image name per line,
// exactly as in the COLMAP model (e.g. "frame_000042.png"); every listed
// frame is held out for testing, every other frame trains. Text after '#' is
// a comment; blank lines and surrounding whitespace are ignored. An unknown
// name is an InputError naming the file and the line.
FrameSplit ReadSplitFile(const std::string& path,
                         const std::vector<std::string>& frame_names);

}  // namespace es

#endif  // EULERSPLAT_CORE_IO_SPLIT_H_
