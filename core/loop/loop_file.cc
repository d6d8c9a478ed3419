#include "core/loop/loop_file.h"

#include <cstring>
#include <fstream>
#include <vector>

#include <glog/logging.h>
#include <opencv2/core.hpp>

#include "core/base/atomic_file.h"
#include "core/io/ply_io.h"
#include "core/loop/loop_frame.h"
#include "core/loop/loop_renderer.h"

namespace es {
namespace {

template <typename T>
void Put(std::string* out, size_t offset, T value) {
  static_assert(sizeof(T) == 4, "header fields are 4 bytes");
  std::memcpy(&(*out)[offset], &value, 4);
}

uint16_t Half(double v) { return cv::float16_t(static_cast<float>(v)).bits(); }

}  // namespace

int64_t WriteLoopFile(const LoopModel& model, const LoopFileOptions& options,
                      const std::string& path) {
  const int n = model.gaussians.size();
  const int w = model.num_dynamic();
  const int l = model.cycle_length;
  const int k_count = model.gaussians.sh_coeffs();

  // Water splats first, in dynamic order, then the static ones.
  std::vector<bool> water(n, false);
  std::vector<int> order(model.dynamic_index);
  for (int g : order) water[g] = true;
  for (int g = 0; g < n; ++g)
    if (!water[g]) order.push_back(g);

  LoopRenderer player(&model, RenderOptions());
  player.Start(0);
  std::vector<uint16_t> table(static_cast<size_t>(l) * w *
                              kLoopFileValuesPerSplat);
  std::string ply;
  for (int f = 0; f < l; ++f) {
    if (f > 0) player.Advance();
    const SplatView& s = player.Compose();
    if (f == 0) {
      const GaussianSet frame0 = CopySplats(s, model.gaussians);
      GaussianSet sorted;
      sorted.sh_degree = frame0.sh_degree;
      for (int g : order) sorted.AppendFrom(frame0, g);
      ply = EncodePly(sorted);
    }
    uint16_t* row = &table[static_cast<size_t>(f) * w *
                           kLoopFileValuesPerSplat];
    for (int k = 0; k < w; ++k, row += kLoopFileValuesPerSplat) {
      const int g = model.dynamic_index[k];
      for (int a = 0; a < 3; ++a) {
        row[a] = Half(s.means[3 * g + a]);
        row[3 + a] = Half(0.5 + kShC0 * s.sh[3 * k_count * g + a]);
      }
      row[6] = Half(Sigmoid(s.opacity_logits[g]));
    }
  }

  const size_t table_offset = (kLoopFileHeaderBytes + ply.size() + 3) / 4 * 4;
  std::string bytes(table_offset + table.size() * sizeof(uint16_t), '\0');
  std::memcpy(&bytes[0], kLoopFileMagic, sizeof(kLoopFileMagic));
  Put<uint32_t>(&bytes, 8, 1);
  Put<uint32_t>(&bytes, 12, n);
  Put<uint32_t>(&bytes, 16, w);
  Put<uint32_t>(&bytes, 20, l);
  Put<float>(&bytes, 24, options.fps);
  for (int c = 0; c < 3; ++c)
    Put<float>(&bytes, 28 + 4 * c, options.background[c]);
  Put<uint32_t>(&bytes, 40, kLoopFileHeaderBytes);
  Put<uint32_t>(&bytes, 44, ply.size());
  std::memcpy(&bytes[kLoopFileHeaderBytes], ply.data(), ply.size());
  std::memcpy(&bytes[table_offset], table.data(),
              table.size() * sizeof(uint16_t));
  WriteFileAtomically(path, [&bytes](std::ofstream& out) {
    out.write(bytes.data(), bytes.size());
  });
  return bytes.size();
}

}  // namespace es
