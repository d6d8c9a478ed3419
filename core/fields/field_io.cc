#include "core/fields/field_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {
namespace {

constexpr char kMotionMagic[] = "eulersplat motion field v1\n";
constexpr char kResidualMagic[] = "eulersplat residual field v1\n";

// Appends records to the stream WriteFileAtomically fills.
class Writer {
 public:
  explicit Writer(std::ofstream* out) : out_(out) {}
  void Raw(const void* data, size_t bytes) {
    out_->write(static_cast<const char*>(data), bytes);
  }
  void Int(int32_t v) { Raw(&v, sizeof(v)); }
  void Real(double v) { Raw(&v, sizeof(v)); }
  void Array(const double* v, int64_t n) {
    Raw(&n, sizeof(n));
    Raw(v, n * sizeof(double));
  }

 private:
  std::ofstream* out_;
};

class Reader {
 public:
  explicit Reader(const std::string& path)
      : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path_ + ": cannot open field file");
    in_.seekg(0, std::ios::end);
    size_ = in_.tellg();
    in_.seekg(0);
  }
  // Rejects a parameter count the rest of the file cannot hold, before the
  // field allocates it (a corrupt header must not allocate gigabytes).
  void CheckFits(double num_doubles, const char* what) {
    const double remaining = size_ - static_cast<double>(in_.tellg());
    if (num_doubles * sizeof(double) > remaining)
      throw InputError(path_ + ": truncated field file (" + what +
                       " options imply more parameters than it holds)");
  }
  void Magic(const char* magic) {
    std::string line(std::char_traits<char>::length(magic), '\0');
    in_.read(line.data(), line.size());
    if (!in_ || line != magic)
      throw InputError(path_ + ": not a field file of this kind (expected '" +
                       std::string(magic, line.size() - 1) + "')");
  }
  void Raw(void* data, size_t bytes) {
    in_.read(static_cast<char*>(data), bytes);
    if (!in_) throw InputError(path_ + ": truncated field file");
  }
  int32_t Int() {
    int32_t v;
    Raw(&v, sizeof(v));
    return v;
  }
  double Real() {
    double v;
    Raw(&v, sizeof(v));
    if (!std::isfinite(v)) throw InputError(path_ + ": non-finite value");
    return v;
  }
  void Array(int expected, std::vector<double>* v, const char* what) {
    int64_t n;
    Raw(&n, sizeof(n));
    if (n != expected)
      throw InputError(path_ + ": " + what + " has " + std::to_string(n) +
                       " parameters, options imply " +
                       std::to_string(expected));
    v->resize(n);
    Raw(v->data(), n * sizeof(double));
    for (double x : *v)
      if (!std::isfinite(x))
        throw InputError(path_ + ": non-finite " + what + " parameter");
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  double size_ = 0;
};

void WriteTriplaneOptions(const TriplaneOptions& o, Writer* w) {
  w->Int(o.resolution);
  w->Int(o.channels);
  w->Int(static_cast<int32_t>(o.combination));
  w->Real(o.init_noise);
}

double TriplaneParams(const TriplaneOptions& o) {
  return 3.0 * o.resolution * o.resolution * o.channels;
}

TriplaneOptions ReadTriplaneOptions(Reader* r) {
  TriplaneOptions o;
  o.resolution = r->Int();
  o.channels = r->Int();
  const int combination = r->Int();
  o.init_noise = r->Real();
  if (o.resolution < 2 || o.resolution > 4096 || o.channels < 1 ||
      o.channels > 1024 || combination < 0 || combination > 2)
    throw InputError(r->path() + ": invalid triplane options");
  r->CheckFits(TriplaneParams(o), "triplane");
  o.combination = static_cast<PlaneCombination>(combination);
  return o;
}

void WriteBox(const Triplane& t, Writer* w) {
  for (int i = 0; i < 3; ++i) w->Real(t.box_min()[i]);
  for (int i = 0; i < 3; ++i) w->Real(t.box_max()[i]);
}

void ReadBox(Reader* r, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  for (int i = 0; i < 3; ++i) (*lo)[i] = r->Real();
  for (int i = 0; i < 3; ++i) (*hi)[i] = r->Real();
  if (((*hi - *lo).array() <= 0).any())
    throw InputError(r->path() + ": empty bounding box");
}

// Both field files end with the box and the parameters.
template <typename Field>
void WriteBoxAndParams(const Field& field, Writer* w) {
  WriteBox(field.triplane(), w);
  w->Array(field.params().triplane, field.triplane().num_params());
  w->Array(field.params().mlp, field.mlp().num_params());
}

template <typename Field, typename Options>
Field ReadBoxAndParams(const Options& options, Reader* r) {
  Eigen::Vector3d lo, hi;
  ReadBox(r, &lo, &hi);
  Field field(options);
  field.SetBox(lo, hi);
  r->Array(field.triplane().num_params(), &field.triplane_params(), "triplane");
  r->Array(field.mlp().num_params(), &field.mlp_params(), "MLP");
  return field;
}

// The triplane's parameters still to come are read first: `triplane_params`.
void CheckMlpShape(int width, int depth, double triplane_params, Reader* r) {
  if (width < 1 || width > 4096 || depth < 0 || depth > 64)
    throw InputError(r->path() + ": invalid MLP shape");
  // Hidden layers alone hold width^2 weights each.
  r->CheckFits(triplane_params + double(width) * width * std::max(depth - 1, 0),
               "MLP");
}

// Every field file: the magic line, the triplane options, the kind's own
// options (`own`), the MLP's shape, the field's output scale (`scale`),
// the last layer's init scale, the seed, then the box and the parameters.
template <typename Field, typename Options, typename WriteOwn>
void SaveField(const Field& field, const std::string& path, const char* magic,
               double Options::*scale, WriteOwn write_own) {
  WriteFileAtomically(path, [&](std::ofstream& out) {
    Writer w(&out);
    w.Raw(magic, std::char_traits<char>::length(magic));
    const Options& o = field.options();
    WriteTriplaneOptions(o.triplane, &w);
    write_own(o, &w);
    w.Int(o.mlp_width);
    w.Int(o.mlp_depth);
    w.Real(o.*scale);
    w.Real(o.last_layer_init_scale);
    w.Int(static_cast<int32_t>(o.seed));
    WriteBoxAndParams(field, &w);
  });
}

template <typename Field, typename Options, typename ReadOwn>
Field LoadField(const std::string& path, const char* magic,
                double Options::*scale, ReadOwn read_own) {
  Reader r(path);
  r.Magic(magic);
  Options o;
  o.triplane = ReadTriplaneOptions(&r);
  read_own(&r, &o);
  o.mlp_width = r.Int();
  o.mlp_depth = r.Int();
  CheckMlpShape(o.mlp_width, o.mlp_depth, TriplaneParams(o.triplane), &r);
  o.*scale = r.Real();
  o.last_layer_init_scale = r.Real();
  o.seed = static_cast<uint32_t>(r.Int());
  return ReadBoxAndParams<Field>(o, &r);
}

// Motion fields have no options of their own.
void WriteNothing(const MotionFieldOptions&, Writer*) {}
void ReadNothing(Reader*, MotionFieldOptions*) {}

void WriteCycleOptions(const ResidualFieldOptions& o, Writer* w) {
  w->Int(o.cycle_length);
  w->Int(o.t_frequencies);
  w->Int(o.p_frequencies);
  w->Int(o.max_cycles);
}

void ReadCycleOptions(Reader* r, ResidualFieldOptions* o) {
  o->cycle_length = r->Int();
  o->t_frequencies = r->Int();
  o->p_frequencies = r->Int();
  o->max_cycles = r->Int();
  if (o->cycle_length < 1 || o->t_frequencies < 0 || o->t_frequencies > 64 ||
      o->p_frequencies < 0 || o->p_frequencies > 64 || o->max_cycles < 1)
    throw InputError(r->path() + ": invalid residual field options");
}

}  // namespace

void SaveMotionField(const MotionField& field, const std::string& path) {
  SaveField(field, path, kMotionMagic, &MotionFieldOptions::velocity_scale,
            WriteNothing);
}

MotionField LoadMotionField(const std::string& path) {
  return LoadField<MotionField>(path, kMotionMagic,
                                &MotionFieldOptions::velocity_scale,
                                ReadNothing);
}

void SaveResidualField(const ResidualField& field, const std::string& path) {
  SaveField(field, path, kResidualMagic, &ResidualFieldOptions::position_scale,
            WriteCycleOptions);
}

ResidualField LoadResidualField(const std::string& path) {
  return LoadField<ResidualField>(path, kResidualMagic,
                                  &ResidualFieldOptions::position_scale,
                                  ReadCycleOptions);
}

}  // namespace es
