#ifndef EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_IO_H_
#define EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_IO_H_

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/model/gaussians.h"
#include "solvers/optim/adam.h"
#include "solvers/optim/frame_sampler.h"

namespace es {

// Little-endian records shared by the Stage-1 and joint checkpoints: plain
// values, length-prefixed (uint64) arrays, and whole GaussianSets.
class CheckpointWriter {
 public:
  explicit CheckpointWriter(std::ofstream* out) : out_(out) {}
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
    for (const GaussianArray& a : kGaussianArrays) Vector(g.*a.values);
  }
  void Adam(const GaussianAdamState& a) {
    Gaussians(a.m);
    Gaussians(a.v);
    Pod<int64_t>(a.step);
  }
  void Sampler(const FrameSampler::State& s) {
    String(s.rng);
    Vector(s.order);
    Pod<int32_t>(s.position);
  }

  // Record(x) writes x as its type's record; CheckpointReader::Record(x)
  // reads it back into x, so a checkpoint lists its records once for both.
  void Record(int64_t v) { Pod(v); }
  void Record(int32_t v) { Pod(v); }
  template <typename T>
  void Record(const std::vector<T>& v) { Vector(v); }
  void Record(const std::vector<std::vector<double>>& vs) { Vectors(vs); }
  void Record(const std::string& s) { String(s); }
  void Record(const GaussianSet& g) { Gaussians(g); }
  void Record(const GaussianAdamState& a) { Adam(a); }
  void Record(const FrameSampler::State& s) { Sampler(s); }

 private:
  std::ofstream* out_;
};

// Reads what CheckpointWriter wrote; every problem throws InputError
// "<path>: not a valid <kind> (<what>)".
class CheckpointReader {
 public:
  CheckpointReader(std::ifstream* in, const std::string& path,
                   const std::string& kind)
      : in_(in), path_(path), kind_(kind) {
    in_->seekg(0, std::ios::end);
    size_ = in_->tellg();
    in_->seekg(0);
  }
  template <typename T>
  T Pod() {
    T v;
    Read(&v, sizeof(T));
    return v;
  }
  template <typename T>
  std::vector<T> Vector() {
    const uint64_t n = Pod<uint64_t>();
    // Checked against the bytes left before allocating: a corrupt length
    // must not allocate gigabytes.
    if (n > RemainingBytes() / sizeof(T)) Fail("truncated");
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
    for (const GaussianArray& a : kGaussianArrays)
      g.*a.values = Vector<double>();
    const size_t n = g.size();
    for (const GaussianArray& a : kGaussianArrays)
      if ((g.*a.values).size() != a.Width(g.sh_coeffs()) * n)
        Fail("inconsistent Gaussian arrays");
    return g;
  }
  GaussianAdamState Adam() {
    GaussianAdamState a;
    a.m = Gaussians();
    a.v = Gaussians();
    a.step = Pod<int64_t>();
    return a;
  }
  FrameSampler::State Sampler() {
    FrameSampler::State s;
    s.rng = String();
    s.order = Vector<int>();
    s.position = Pod<int32_t>();
    if (s.position < 0 || s.position > static_cast<int>(s.order.size()))
      Fail("frame sampler position out of range");
    return s;
  }
  void Record(int64_t& v) { v = Pod<int64_t>(); }
  void Record(int32_t& v) { v = Pod<int32_t>(); }
  template <typename T>
  void Record(std::vector<T>& v) { v = Vector<T>(); }
  void Record(std::vector<std::vector<double>>& vs) { vs = Vectors(); }
  void Record(std::string& s) { s = String(); }
  void Record(GaussianSet& g) { g = Gaussians(); }
  void Record(GaussianAdamState& a) { a = Adam(); }
  void Record(FrameSampler::State& s) { s = Sampler(); }

  [[noreturn]] void Fail(const std::string& what) {
    throw InputError(path_ + ": not a valid " + kind_ + " (" + what + ")");
  }

 private:
  uint64_t RemainingBytes() {
    const std::streamoff at = in_->tellg();
    return at < 0 || at > size_ ? 0 : static_cast<uint64_t>(size_ - at);
  }
  void Read(void* dst, size_t bytes) {
    in_->read(static_cast<char*>(dst), bytes);
    if (!*in_) Fail("truncated");
  }
  std::ifstream* in_;
  std::string path_, kind_;
  std::streamoff size_ = 0;
};

// Every checkpoint file starts with an 8-byte tag naming its kind and
// version.
using CheckpointMagic = char[8];

// Writes PATH atomically (core/base/atomic_file.h): `write_records(
// CheckpointWriter&)` fills a temporary file that then replaces PATH, so a
// run killed mid-write keeps its previous checkpoint, and a failed write
// (disk full) throws InputError and keeps it too.
template <typename WriteRecords>
void WriteCheckpointFile(const std::string& path, const CheckpointMagic& magic,
                         WriteRecords write_records) {
  WriteFileAtomically(path, [&](std::ofstream& out) {
    out.write(magic, sizeof(CheckpointMagic));
    CheckpointWriter writer(&out);
    write_records(writer);
  });
}

// Opens PATH, checks its tag and returns `read_records(CheckpointReader&)`;
// problems throw InputError naming PATH and `kind`.
template <typename ReadRecords>
auto ReadCheckpointFile(const std::string& path, const std::string& kind,
                        const CheckpointMagic& magic,
                        ReadRecords read_records) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open " + kind);
  CheckpointReader reader(&in, path, kind);
  CheckpointMagic tag;
  in.read(tag, sizeof(tag));
  if (!in || !std::equal(tag, tag + sizeof(tag), magic))
    reader.Fail("wrong magic or version");
  return read_records(reader);
}

}  // namespace es

#endif  // EULERSPLAT_SOLVERS_CHECKPOINT_CHECKPOINT_IO_H_
