#include "solvers/checkpoint/joint_checkpoint.h"

#include <cmath>

#include "solvers/checkpoint/checkpoint_io.h"

namespace es {
namespace {

constexpr CheckpointMagic kMagic = {'E', 'S', 'J', 'C', 'K', 'P', 'T', '2'};

bool SameShapes(const std::vector<std::vector<double>>& a,
                const std::vector<std::vector<double>>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].size() != b[i].size()) return false;
  return true;
}

// The records in file order. `io` is a CheckpointWriter (and `c` const) or
// a CheckpointReader.
template <typename Io, typename C>
void Records(Io& io, C& c) {
  io.Record(c.iteration);
  io.Record(c.gaussians);
  io.Record(c.adam);
  io.Record(c.dynamic_index);
  io.Record(c.start_times);
  io.Record(c.field_params);
  io.Record(c.field_m);
  io.Record(c.field_v);
  io.Record(c.field_boxes);
  io.Record(c.field_step);
  io.Record(c.sampler);
  io.Record(c.rng);
  io.Record(c.batch_frames);
}

}  // namespace

void WriteJointCheckpoint(const JointCheckpoint& c, const std::string& path) {
  WriteCheckpointFile(path, kMagic,
                      [&c](CheckpointWriter& w) { Records(w, c); });
}

JointCheckpoint ReadJointCheckpoint(const std::string& path) {
  return ReadCheckpointFile(
      path, "joint checkpoint", kMagic, [](CheckpointReader& r) {
        JointCheckpoint c;
        Records(r, c);
        if (c.batch_frames < 1) r.Fail("batch of no frames");
        const int n = c.gaussians.size();
        if (c.adam.m.size() != n || c.adam.v.size() != n ||
            c.dynamic_index.size() != c.start_times.size() ||
            !SameShapes(c.field_params, c.field_m) ||
            !SameShapes(c.field_params, c.field_v) ||
            c.field_boxes.size() != 3 * c.field_params.size())
          r.Fail("inconsistent sizes");
        // Boxes go to Triplane::SetBox, which CHECKs they are not empty.
        for (size_t f = 0; f + 6 <= c.field_boxes.size(); f += 6) {
          for (int a = 0; a < 3; ++a) {
            const double lo = c.field_boxes[f + a];
            const double hi = c.field_boxes[f + 3 + a];
            if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
              r.Fail("empty or non-finite field box");
          }
        }
        for (size_t k = 0; k < c.dynamic_index.size(); ++k) {
          if (c.dynamic_index[k] < 0 || c.dynamic_index[k] >= n ||
              (k > 0 && c.dynamic_index[k] <= c.dynamic_index[k - 1]))
            r.Fail("dynamic indices out of range or not ascending");
        }
        return c;
      });
}

}  // namespace es
