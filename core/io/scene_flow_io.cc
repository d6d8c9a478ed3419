#include "core/io/scene_flow_io.h"

#include <cmath>
#include <cstdint>
#include <fstream>

#include "core/io/atomic_file.h"
#include "core/io/input_error.h"

namespace es {
namespace {

constexpr char kMagic[] = "eulersplat scene flow samples v1\n";
constexpr int kValuesPerSample = 6;

}  // namespace

void SaveSceneFlowSamples(const std::vector<SceneFlowSample>& samples,
                          const std::string& path) {
  WriteFileAtomically(path, [&samples](std::ofstream& out) {
    out.write(kMagic, sizeof(kMagic) - 1);
    const int64_t count = static_cast<int64_t>(samples.size());
    out.write(reinterpret_cast<const char*>(&count), sizeof(count));
    for (const SceneFlowSample& s : samples) {
      const double values[kValuesPerSample] = {s.x[0], s.x[1], s.x[2],
                                               s.v[0], s.v[1], s.v[2]};
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
  if (!in || magic != kMagic)
    throw InputError(path + ": not a scene-flow samples file (expected '" +
                     std::string(kMagic, sizeof(kMagic) - 2) + "')");
  int64_t count = -1;
  in.read(reinterpret_cast<char*>(&count), sizeof(count));
  const double header = static_cast<double>(magic.size() + sizeof(count));
  if (!in || count < 0 ||
      static_cast<double>(count) * kValuesPerSample * sizeof(double) !=
          size - header)
    throw InputError(path + ": truncated or corrupt scene-flow samples "
                            "(the count does not match the file size)");
  std::vector<SceneFlowSample> samples(count);
  for (SceneFlowSample& s : samples) {
    double values[kValuesPerSample];
    in.read(reinterpret_cast<char*>(values), sizeof(values));
    for (double v : values) {
      if (!std::isfinite(v))
        throw InputError(path + ": non-finite scene-flow sample");
    }
    s.x = Eigen::Vector3d(values[0], values[1], values[2]);
    s.v = Eigen::Vector3d(values[3], values[4], values[5]);
  }
  if (!in) throw InputError(path + ": truncated scene-flow samples");
  return samples;
}

}  // namespace es
