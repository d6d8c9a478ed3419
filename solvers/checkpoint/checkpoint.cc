#include "solvers/checkpoint/checkpoint.h"

#include "solvers/checkpoint/checkpoint_io.h"

namespace es {
namespace {

constexpr CheckpointMagic kMagic = {'E', 'S', 'C', 'K', 'P', 'T', '0', '2'};

}  // namespace

void WriteCheckpoint(const Checkpoint& c, const std::string& path) {
  WriteCheckpointFile(path, kMagic, [&c](CheckpointWriter& w) {
    w.Pod<int64_t>(c.iteration);
    w.Gaussians(c.gaussians);
    w.Adam(c.adam);
    w.Sampler(c.sampler);
    w.String(c.rng);
    w.Vector(c.grad_sum);
    w.Vector(c.grad_count);
    w.Vector(c.max_radius);
    w.Pod<int32_t>(c.batch_frames);
  });
}

Checkpoint ReadCheckpoint(const std::string& path) {
  return ReadCheckpointFile(
      path, "checkpoint", kMagic, [](CheckpointReader& r) {
        Checkpoint c;
        c.iteration = r.Pod<int64_t>();
        c.gaussians = r.Gaussians();
        c.adam = r.Adam();
        c.sampler = r.Sampler();
        c.rng = r.String();
        c.grad_sum = r.Vector<double>();
        c.grad_count = r.Vector<double>();
        c.max_radius = r.Vector<double>();
        c.batch_frames = r.Pod<int32_t>();
        if (c.batch_frames < 1) r.Fail("batch of no frames");
        const size_t n = c.gaussians.size();
        if (c.adam.m.size() != static_cast<int>(n) ||
            c.adam.v.size() != static_cast<int>(n) || c.grad_sum.size() != n ||
            c.grad_count.size() != n || c.max_radius.size() != n)
          r.Fail("inconsistent sizes");
        return c;
      });
}

}  // namespace es
