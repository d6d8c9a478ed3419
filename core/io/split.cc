#include "core/io/split.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/base/input_error.h"

namespace es {
namespace {

// Part `i` of `total` items shared as evenly as possible among `parts`.
int EvenShare(int total, int parts, int i) {
  return static_cast<int>((static_cast<int64_t>(i + 1) * total) / parts -
                          (static_cast<int64_t>(i) * total) / parts);
}

FrameSplit FromTestFlags(const std::vector<bool>& is_test) {
  FrameSplit split;
  for (size_t i = 0; i < is_test.size(); ++i)
    (is_test[i] ? split.test : split.train).push_back(i);
  return split;
}

}  // namespace

FrameSplit DefaultSplit(int num_frames, int num_segments,
                        double test_fraction) {
  if (!(test_fraction >= 0 && test_fraction < 1))
    throw InputError("test fraction must be in [0, 1), got " +
                     std::to_string(test_fraction));
  if (num_segments < 0)
    throw InputError("number of test segments must be >= 0, got " +
                     std::to_string(num_segments));
  std::vector<bool> is_test(num_frames, false);
  const int wanted = std::lround(test_fraction * num_frames);
  if (num_frames < 2 || num_segments == 0 || test_fraction == 0)
    return FromTestFlags(is_test);

  // As many segments (up to num_segments) as leave a training frame on both
  // sides of each; failing that, one run that keeps a training frame.
  int segments = 1;
  int num_test = std::min(std::max(wanted, 1), num_frames - 1);
  for (int s = num_segments; s >= 1; --s) {
    const int t = std::min(std::max(wanted, s), num_frames - s - 1);
    if (t >= s) {
      segments = s;
      num_test = t;
      break;
    }
  }
  // Training frames fill the segments + 1 gaps around the test runs.
  const int num_train = num_frames - num_test;
  int frame = 0;
  for (int s = 0; s < segments; ++s) {
    frame += EvenShare(num_train, segments + 1, s);
    const int length = EvenShare(num_test, segments, s);
    for (int j = 0; j < length; ++j) is_test[frame++] = true;
  }
  return FromTestFlags(is_test);
}

FrameSplit ReadSplitFile(const std::string& path,
                         const std::vector<std::string>& frame_names) {
  std::ifstream file(path);
  if (!std::filesystem::is_regular_file(path) || !file)
    throw InputError(path + ": cannot open file");
  std::map<std::string, int> index;
  for (size_t i = 0; i < frame_names.size(); ++i) index[frame_names[i]] = i;
  std::vector<bool> is_test(frame_names.size(), false);
  std::string line;
  for (int line_number = 1; std::getline(file, line); ++line_number) {
    line = line.substr(0, line.find('#'));
    const size_t begin = line.find_first_not_of(" \t\r");
    if (begin == std::string::npos) continue;
    const size_t end = line.find_last_not_of(" \t\r");
    const std::string name = line.substr(begin, end - begin + 1);
    const auto it = index.find(name);
    if (it == index.end())
      throw InputError(path + ":" + std::to_string(line_number) +
                       ": unknown image name '" + name + "'");
    is_test[it->second] = true;
  }
  return FromTestFlags(is_test);
}

}  // namespace es
