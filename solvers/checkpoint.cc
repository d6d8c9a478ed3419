#include "solvers/checkpoint.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/input_error.h"
#include "solvers/checkpoint_io.h"

namespace es {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'C', 'K', 'P', 'T', '0', '1'};

}  // namespace

void WriteCheckpoint(const Checkpoint& c, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(tmp + ": cannot open for writing");
    CheckpointWriter w(&out);
    out.write(kMagic, sizeof(kMagic));
    w.Pod<int64_t>(c.iteration);
    w.Gaussians(c.gaussians);
    w.Gaussians(c.adam_m);
    w.Gaussians(c.adam_v);
    w.Pod<int64_t>(c.adam_step);
    w.String(c.sampler.rng);
    w.Vector(c.sampler.order);
    w.Pod<int32_t>(c.sampler.position);
    w.String(c.rng);
    w.Vector(c.grad_sum);
    w.Vector(c.grad_count);
    w.Vector(c.max_radius);
    out.flush();
    if (!out) throw InputError(tmp + ": write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw InputError(path + ": cannot rename " + tmp + " over it");
}

Checkpoint ReadCheckpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open checkpoint");
  CheckpointReader r(&in, path, "checkpoint");
  char magic[sizeof(kMagic)];
  in.read(magic, sizeof(magic));
  if (!in || !std::equal(magic, magic + sizeof(magic), kMagic))
    r.Fail("wrong magic or version");
  Checkpoint c;
  c.iteration = r.Pod<int64_t>();
  c.gaussians = r.Gaussians();
  c.adam_m = r.Gaussians();
  c.adam_v = r.Gaussians();
  c.adam_step = r.Pod<int64_t>();
  c.sampler.rng = r.String();
  c.sampler.order = r.Vector<int>();
  c.sampler.position = r.Pod<int32_t>();
  c.rng = r.String();
  c.grad_sum = r.Vector<double>();
  c.grad_count = r.Vector<double>();
  c.max_radius = r.Vector<double>();
  const size_t n = c.gaussians.size();
  if (c.adam_m.size() != static_cast<int>(n) ||
      c.adam_v.size() != static_cast<int>(n) || c.grad_sum.size() != n ||
      c.grad_count.size() != n || c.max_radius.size() != n ||
      c.sampler.position < 0 ||
      c.sampler.position > static_cast<int>(c.sampler.order.size()))
    r.Fail("inconsistent sizes");
  return c;
}

}  // namespace es
