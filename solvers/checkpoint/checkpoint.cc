#include "solvers/checkpoint/checkpoint.h"

#include "solvers/checkpoint/checkpoint_io.h"

namespace es {
namespace {

constexpr CheckpointMagic kMagic = {'E', 'S', 'C', 'K', 'P', 'T', '0', '2'};

// The records in file order. `io` is a CheckpointWriter (and `c` const) or
// a CheckpointReader.
template <typename Io, typename C>
void Records(Io& io, C& c) {
  io.Record(c.iteration);
  io.Record(c.gaussians);
  io.Record(c.adam);
  io.Record(c.sampler);
  io.Record(c.rng);
  io.Record(c.grad_sum);
  io.Record(c.grad_count);
  io.Record(c.max_radius);
  io.Record(c.batch_frames);
}

}  // namespace

void WriteCheckpoint(const Checkpoint& c, const std::string& path) {
  WriteCheckpointFile(path, kMagic,
                      [&c](CheckpointWriter& w) { Records(w, c); });
}

Checkpoint ReadCheckpoint(const std::string& path) {
  return ReadCheckpointFile(
      path, "checkpoint", kMagic, [](CheckpointReader& r) {
        Checkpoint c;
        Records(r, c);
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
