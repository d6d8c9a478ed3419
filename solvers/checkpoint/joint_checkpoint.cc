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

}  // namespace

void WriteJointCheckpoint(const JointCheckpoint& c, const std::string& path) {
  WriteCheckpointFile(path, kMagic, [&c](CheckpointWriter& w) {
    w.Pod<int64_t>(c.iteration);
    w.Gaussians(c.gaussians);
    w.Adam(c.adam);
    w.Vector(c.dynamic_index);
    w.Vector(c.start_times);
    w.Vectors(c.field_params);
    w.Vectors(c.field_m);
    w.Vectors(c.field_v);
    w.Vector(c.field_boxes);
    w.Pod<int64_t>(c.field_step);
    w.Sampler(c.sampler);
    w.String(c.rng);
    w.Pod<int32_t>(c.batch_frames);
  });
}

JointCheckpoint ReadJointCheckpoint(const std::string& path) {
  return ReadCheckpointFile(
      path, "joint checkpoint", kMagic, [](CheckpointReader& r) {
        JointCheckpoint c;
        c.iteration = r.Pod<int64_t>();
        c.gaussians = r.Gaussians();
        c.adam = r.Adam();
        c.dynamic_index = r.Vector<int>();
        c.start_times = r.Vector<int>();
        c.field_params = r.Vectors();
        c.field_m = r.Vectors();
        c.field_v = r.Vectors();
        c.field_boxes = r.Vector<double>();
        c.field_step = r.Pod<int64_t>();
        c.sampler = r.Sampler();
        c.rng = r.String();
        c.batch_frames = r.Pod<int32_t>();
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
