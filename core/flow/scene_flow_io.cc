#include "core/flow/scene_flow_io.h"

#include <cmath>
#include <cstdint>
#include <fstream>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {
namespace {

// v2 adds each sample's unseen direction; v1 files (without it) still load.
constexpr char kMagic[] = "eulersplat scene flow samples v2\n";
constexpr char kMagicV1[] = "eulersplat scene flow samples v1\n";
constexpr int kValuesPerSample = 9;
constexpr int kValuesPerSampleV1 = 6;

}  // namespace

void SaveSceneFlowSamples(const std::vector<SceneFlowSample>& samples,
                          const std::string& path) {
  WriteFileAtomically(path, [&samples](std::ofstream& out) {
    out.write(kMagic, sizeof(kMagic) - 1);
    const int64_t count = static_cast<int64_t>(samples.size());
    out.write(reinterpret_cast<const char*>(&count), sizeof(count));
    for (const SceneFlowSample& s : samples) {
      const double values[kValuesPerSample] = {
          s.x[0], s.x[1], s.x[2],      s.v[0],     s.v[1],
          s.v[2], s.unseen[0], s.unseen[1], s.unseen[2]};
      out.write(reinterpret_cast<const char*>(values), sizeof(values));
    }
  });
}

std::vector<SceneFlowSample> LoadSceneFlowSamples(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scene-flow samples");
  in.seekg(0, std::ios::end);
  const double size = static_cast<double>(in.tellg());
  in.seekg(0);
  std::string magic(sizeof(kMagic) - 1, '\0');
  in.read(magic.data(), magic.size());
  if (!in || (magic != kMagic && magic != kMagicV1))
    throw InputError(path + ": not a scene-flow samples file (expected '" +
                     std::string(kMagic, sizeof(kMagic) - 2) + "')");
  const int per_sample =
      magic == kMagic ? kValuesPerSample : kValuesPerSampleV1;
  int64_t count = -1;
  in.read(reinterpret_cast<char*>(&count), sizeof(count));
  const double header = static_cast<double>(magic.size() + sizeof(count));
  if (!in || count < 0 ||
      static_cast<double>(count) * per_sample * sizeof(double) !=
          size - header)
    throw InputError(path + ": truncated or corrupt scene-flow samples "
                            "(the count does not match the file size)");
  std::vector<SceneFlowSample> samples(count);
  for (SceneFlowSample& s : samples) {
    double values[kValuesPerSample] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    in.read(reinterpret_cast<char*>(values), per_sample * sizeof(double));
    for (double v : values) {
      if (!std::isfinite(v))
        throw InputError(path + ": non-finite scene-flow sample");
    }
    s.x = Eigen::Vector3d(values[0], values[1], values[2]);
    s.v = Eigen::Vector3d(values[3], values[4], values[5]);
    s.unseen = Eigen::Vector3d(values[6], values[7], values[8]);
    if (s.unseen.norm() > 1 + 1e-6)
      throw InputError(path + ": a scene-flow sample's unseen direction is "
                              "longer than a unit vector");
  }
  if (!in) throw InputError(path + ": truncated scene-flow samples");
  return samples;
}

}  // namespace es
