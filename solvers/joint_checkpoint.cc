#include "solvers/joint_checkpoint.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/input_error.h"

namespace es {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'J', 'C', 'K', 'P', 'T', '1'};

class Writer {
 public:
  explicit Writer(std::ofstream* out) : out_(out) {}
  template <typename T>
  void Pod(const T& v) {
    out_->write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <typename T>
  void Vector(const std::vector<T>& v) {
    Pod<uint64_t>(v.size());
    out_->write(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void String(const std::string& s) {
    Vector(std::vector<char>(s.begin(), s.end()));
  }
  void Vectors(const std::vector<std::vector<double>>& vs) {
    Pod<uint64_t>(vs.size());
    for (const auto& v : vs) Vector(v);
  }
  void Gaussians(const GaussianSet& g) {
    Pod<int32_t>(g.sh_degree);
    for (const auto* v : {&g.means, &g.log_scales, &g.quats,
                          &g.opacity_logits, &g.sh, &g.dynamic_logits})
      Vector(*v);
  }

 private:
  std::ofstream* out_;
};

class Reader {
 public:
  Reader(std::ifstream* in, const std::string& path) : in_(in), path_(path) {}
  template <typename T>
  T Pod() {
    T v;
    Read(&v, sizeof(T));
    return v;
  }
  template <typename T>
  std::vector<T> Vector() {
    const uint64_t n = Pod<uint64_t>();
    if (n > (uint64_t{1} << 40) / sizeof(T)) Fail("implausible array size");
    std::vector<T> v(n);
    Read(v.data(), n * sizeof(T));
    return v;
  }
  std::string String() {
    const std::vector<char> c = Vector<char>();
    return std::string(c.begin(), c.end());
  }
  std::vector<std::vector<double>> Vectors() {
    const uint64_t n = Pod<uint64_t>();
    if (n > 16) Fail("implausible number of field blocks");
    std::vector<std::vector<double>> vs(n);
    for (auto& v : vs) v = Vector<double>();
    return vs;
  }
  GaussianSet Gaussians() {
    GaussianSet g;
    g.sh_degree = Pod<int32_t>();
    if (g.sh_degree < 0 || g.sh_degree > kMaxShDegree) Fail("bad SH degree");
    for (auto* v : {&g.means, &g.log_scales, &g.quats, &g.opacity_logits,
                    &g.sh, &g.dynamic_logits})
      *v = Vector<double>();
    const size_t n = g.opacity_logits.size();
    if (g.means.size() != 3 * n || g.log_scales.size() != 3 * n ||
        g.quats.size() != 4 * n || g.sh.size() != 3 * n * g.sh_coeffs() ||
        g.dynamic_logits.size() != n)
      Fail("inconsistent Gaussian arrays");
    return g;
  }
  [[noreturn]] void Fail(const std::string& what) {
    throw InputError(path_ + ": not a valid joint checkpoint (" + what + ")");
  }

 private:
  void Read(void* dst, size_t bytes) {
    in_->read(static_cast<char*>(dst), bytes);
    if (!*in_) Fail("truncated");
  }
  std::ifstream* in_;
  std::string path_;
};

bool SameShapes(const std::vector<std::vector<double>>& a,
                const std::vector<std::vector<double>>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].size() != b[i].size()) return false;
  return true;
}

}  // namespace

void WriteJointCheckpoint(const JointCheckpoint& c, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(tmp + ": cannot open for writing");
    Writer w(&out);
    out.write(kMagic, sizeof(kMagic));
    w.Pod<int64_t>(c.iteration);
    w.Gaussians(c.gaussians);
    w.Gaussians(c.adam_m);
    w.Gaussians(c.adam_v);
    w.Pod<int64_t>(c.adam_step);
    w.Vector(c.dynamic_index);
    w.Vector(c.start_times);
    w.Vectors(c.field_params);
    w.Vectors(c.field_m);
    w.Vectors(c.field_v);
    w.Vector(c.field_boxes);
    w.Pod<int64_t>(c.field_step);
    w.String(c.sampler.rng);
    w.Vector(c.sampler.order);
    w.Pod<int32_t>(c.sampler.position);
    w.String(c.rng);
    out.flush();
    if (!out) throw InputError(tmp + ": write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw InputError(path + ": cannot rename " + tmp + " over it");
}

JointCheckpoint ReadJointCheckpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open joint checkpoint");
  Reader r(&in, path);
  char magic[sizeof(kMagic)];
  in.read(magic, sizeof(magic));
  if (!in || !std::equal(magic, magic + sizeof(magic), kMagic))
    r.Fail("wrong magic or version");
  JointCheckpoint c;
  c.iteration = r.Pod<int64_t>();
  c.gaussians = r.Gaussians();
  c.adam_m = r.Gaussians();
  c.adam_v = r.Gaussians();
  c.adam_step = r.Pod<int64_t>();
  c.dynamic_index = r.Vector<int>();
  c.start_times = r.Vector<int>();
  c.field_params = r.Vectors();
  c.field_m = r.Vectors();
  c.field_v = r.Vectors();
  c.field_boxes = r.Vector<double>();
  c.field_step = r.Pod<int64_t>();
  c.sampler.rng = r.String();
  c.sampler.order = r.Vector<int>();
  c.sampler.position = r.Pod<int32_t>();
  c.rng = r.String();
  const int n = c.gaussians.size();
  if (c.adam_m.size() != n || c.adam_v.size() != n ||
      c.dynamic_index.size() != c.start_times.size() ||
      !SameShapes(c.field_params, c.field_m) ||
      !SameShapes(c.field_params, c.field_v) ||
      c.field_boxes.size() != 3 * c.field_params.size() ||
      c.sampler.position < 0 ||
      c.sampler.position > static_cast<int>(c.sampler.order.size()))
    r.Fail("inconsistent sizes");
  for (size_t k = 0; k < c.dynamic_index.size(); ++k) {
    if (c.dynamic_index[k] < 0 || c.dynamic_index[k] >= n ||
        (k > 0 && c.dynamic_index[k] <= c.dynamic_index[k - 1]))
      r.Fail("dynamic indices out of range or not ascending");
  }
  return c;
}

}  // namespace es
