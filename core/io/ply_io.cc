#include "core/io/ply_io.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <glog/logging.h>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"

namespace es {
namespace {

enum class PlyType {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

bool ParsePlyType(const std::string& name, PlyType* type) {
  static const struct {
    const char* name;
    PlyType type;
  } kTypes[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},
      {"uchar", PlyType::kUint8},    {"uint8", PlyType::kUint8},
      {"short", PlyType::kInt16},    {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},
      {"int", PlyType::kInt32},      {"int32", PlyType::kInt32},
      {"uint", PlyType::kUint32},    {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32},
      {"double", PlyType::kFloat64}, {"float64", PlyType::kFloat64},
  };
  for (const auto& t : kTypes) {
    if (name == t.name) {
      *type = t.type;
      return true;
    }
  }
  return false;
}

size_t PlyTypeSize(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

template <typename T>
double Load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // little-endian host
  return static_cast<double>(v);
}

double LoadPlyValue(PlyType type, const char* p) {
  switch (type) {
    case PlyType::kInt8:
      return Load<int8_t>(p);
    case PlyType::kUint8:
      return Load<uint8_t>(p);
    case PlyType::kInt16:
      return Load<int16_t>(p);
    case PlyType::kUint16:
      return Load<uint16_t>(p);
    case PlyType::kInt32:
      return Load<int32_t>(p);
    case PlyType::kUint32:
      return Load<uint32_t>(p);
    case PlyType::kFloat32:
      return Load<float>(p);
    case PlyType::kFloat64:
      return Load<double>(p);
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // lists only
};

struct PlyElement {
  std::string name;
  int64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool binary = true;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;  // first byte after "end_header\n"
};

PlyHeader ParseHeader(const std::string& path, const std::string& data) {
  auto fail = [&path](const std::string& message) {
    throw InputError(path + ": bad PLY header: " + message);
  };
  PlyHeader header;
  size_t pos = 0;
  bool has_format = false;
  for (int line_number = 1;; ++line_number) {
    const size_t end = data.find('\n', pos);
    if (end == std::string::npos) fail("no end_header line");
    std::istringstream line(data.substr(pos, end - pos));
    pos = end + 1;
    std::string keyword;
    line >> keyword;
    if (line_number == 1) {
      if (keyword != "ply") fail("file does not start with 'ply'");
      continue;
    }
    if (keyword == "end_header") break;
    if (keyword == "comment" || keyword == "obj_info" || keyword.empty())
      continue;
    if (keyword == "format") {
      std::string format;
      line >> format;
      if (format == "ascii") {
        header.binary = false;
      } else if (format != "binary_little_endian") {
        fail("unsupported format '" + format + "'");
      }
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      if (!(line >> element.name >> element.count) || element.count < 0)
        fail("bad element line " + std::to_string(line_number));
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) fail("property before any element");
      PlyProperty property;
      std::string type;
      line >> type;
      if (type == "list") {
        std::string count_type, item_type;
        line >> count_type >> item_type;
        property.is_list = true;
        if (!ParsePlyType(count_type, &property.count_type) ||
            !ParsePlyType(item_type, &property.type))
          fail("bad list type on line " + std::to_string(line_number));
      } else if (!ParsePlyType(type, &property.type)) {
        fail("unknown type '" + type + "' on line " +
             std::to_string(line_number));
      }
      if (!(line >> property.name))
        fail("property without a name on line " + std::to_string(line_number));
      header.elements.back().properties.push_back(property);
    } else {
      fail("unknown keyword '" + keyword + "' on line " +
           std::to_string(line_number));
    }
  }
  if (!has_format) fail("no format line");
  header.body_offset = pos;
  return header;
}

// Reads the values of one element row at a time, binary or ascii. List
// properties are read and dropped (3DGS vertices have none).
class RowReader {
 public:
  RowReader(const std::string& path, const std::string& data,
            const PlyHeader& header)
      : path_(path),
        data_(data),
        binary_(header.binary),
        pos_(header.body_offset) {}

  // Reads one row of `element` into values (one per non-list property).
  void Read(const PlyElement& element, int64_t row,
            std::vector<double>* values) {
    values->clear();
    for (const PlyProperty& p : element.properties) {
      if (p.is_list) {
        const int64_t count = ListLength(p, element, row);
        for (int64_t i = 0; i < count; ++i) Value(p.type, element, row);
      } else {
        values->push_back(Value(p.type, element, row));
      }
    }
  }

  // Skips every row of an element the reader does not use. An element
  // without properties occupies no bytes, whatever count it announces.
  void Skip(const PlyElement& element) {
    if (element.properties.empty()) return;
    std::vector<double> values;
    for (int64_t row = 0; row < element.count; ++row)
      Read(element, row, &values);
  }

 private:
  // A list's length is stored in any PLY type, float included: it must be a
  // whole number, and each item takes at least a byte, so a length beyond
  // the remaining bytes is a truncated file (checked before any cast).
  int64_t ListLength(const PlyProperty& p, const PlyElement& element,
                     int64_t row) {
    const double count = Value(p.count_type, element, row);
    if (!(count >= 0) || count != std::floor(count))
      Fail(element, row, "bad list length");
    if (count > static_cast<double>(data_.size() - pos_))
      Fail(element, row, "truncated file");
    return static_cast<int64_t>(count);
  }

  double Value(PlyType type, const PlyElement& element, int64_t row) {
    if (binary_) {
      const size_t size = PlyTypeSize(type);
      if (data_.size() - pos_ < size) Fail(element, row, "truncated file");
      const double v = LoadPlyValue(type, data_.data() + pos_);
      pos_ += size;
      return v;
    }
    const size_t begin = data_.find_first_not_of(" \t\r\n", pos_);
    if (begin == std::string::npos) Fail(element, row, "truncated file");
    const char* start = data_.c_str() + begin;
    char* end = nullptr;
    const double v = std::strtod(start, &end);
    if (end == start || (*end != '\0' && !std::isspace(*end)))
      Fail(element, row, "bad number");
    pos_ = end - data_.c_str();
    return v;
  }

  [[noreturn]] void Fail(const PlyElement& element, int64_t row,
                         const std::string& message) const {
    throw InputError(path_ + ": " + message + " in element '" + element.name +
                     "' row " + std::to_string(row) + " of " +
                     std::to_string(element.count));
  }

  const std::string& path_;
  const std::string& data_;
  bool binary_;
  size_t pos_;
};

// Where a vertex property goes in a GaussianSet.
enum class Field {
  kIgnored,
  kMean,
  kShDc,
  kShRest,
  kOpacity,
  kScale,
  kRot,
  kDynamic
};

struct Target {
  Field field = Field::kIgnored;
  int index = 0;
};

// Parses "<prefix><int>" into index; false if name has another form.
bool IndexedName(const std::string& name, const std::string& prefix,
                 int* index) {
  if (name.compare(0, prefix.size(), prefix) != 0 ||
      name.size() == prefix.size())
    return false;
  const std::string digits = name.substr(prefix.size());
  if (digits.find_first_not_of("0123456789") != std::string::npos ||
      digits.size() > 6)
    return false;
  *index = std::stoi(digits);
  return true;
}

Target TargetOf(const std::string& name) {
  static const char* kAxes[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (name == kAxes[i]) return {Field::kMean, i};
  if (name == "opacity") return {Field::kOpacity, 0};
  if (name == "dynamic_logit") return {Field::kDynamic, 0};
  int i = 0;
  if (IndexedName(name, "f_dc_", &i) && i < 3) return {Field::kShDc, i};
  if (IndexedName(name, "f_rest_", &i)) return {Field::kShRest, i};
  if (IndexedName(name, "scale_", &i) && i < 3) return {Field::kScale, i};
  if (IndexedName(name, "rot_", &i) && i < 4) return {Field::kRot, i};
  return {};
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!std::filesystem::is_regular_file(path) || !file)
    throw InputError(path + ": cannot open file");
  file.seekg(0, std::ios::end);
  std::string data(static_cast<size_t>(file.tellg()), '\0');
  file.seekg(0);
  if (!file.read(data.data(), data.size()))
    throw InputError(path + ": read error");
  return data;
}

// Rejects element counts the file is too small to hold before anything is
// allocated for them (every value takes at least one byte, even in ascii).
void CheckSizeFits(const std::string& path, const std::string& data,
                   const PlyHeader& header, int last_element) {
  const double available = data.size() - header.body_offset;
  double needed = 0;
  for (int e = 0; e <= last_element; ++e) {
    const PlyElement& element = header.elements[e];
    double row = 0;
    for (const PlyProperty& p : element.properties)
      row += header.binary ? PlyTypeSize(p.is_list ? p.count_type : p.type) : 1;
    needed += row * element.count;
  }
  if (needed > available ||
      header.elements[last_element].count > std::numeric_limits<int>::max())
    throw InputError(path + ": truncated file (header announces " +
                     std::to_string(header.elements[last_element].count) +
                     " vertices)");
}

// The vertex element (the last one of that name); the elements before it are
// skipped, those after it are never read.
int VertexElementIndex(const std::string& path, const PlyHeader& header) {
  int vertex_index = -1;
  for (size_t e = 0; e < header.elements.size(); ++e)
    if (header.elements[e].name == "vertex") vertex_index = e;
  if (vertex_index < 0) throw InputError(path + ": no 'vertex' element");
  return vertex_index;
}

// Where each non-list vertex property goes, and the SH degree its f_rest
// count implies.
struct VertexLayout {
  std::vector<Target> targets;  // one per non-list property, in file order
  int sh_degree = 0;
};

// Maps the vertex's non-list properties to fields and checks that every
// required one is present exactly once and that the f_rest indices are
// 0..n-1 for an n of some SH degree.
VertexLayout MapVertexProperties(const std::string& path,
                                 const PlyElement& vertex) {
  VertexLayout layout;
  std::vector<int> seen_rest;
  int seen[8][4] = {};
  for (const PlyProperty& p : vertex.properties) {
    if (p.is_list) continue;
    const Target t = TargetOf(p.name);
    layout.targets.push_back(t);
    if (t.field == Field::kShRest) {
      seen_rest.push_back(t.index);
    } else if (t.field != Field::kIgnored) {
      if (seen[static_cast<int>(t.field)][t.index]++ > 0)
        throw InputError(path + ": duplicate property '" + p.name + "'");
    }
  }
  const struct {
    Field field;
    int count;
    const char* name;
  } kRequired[] = {
      {Field::kMean, 3, "x/y/z"},      {Field::kShDc, 3, "f_dc_"},
      {Field::kOpacity, 1, "opacity"}, {Field::kScale, 3, "scale_"},
      {Field::kRot, 4, "rot_"},
  };
  for (const auto& r : kRequired) {
    for (int i = 0; i < r.count; ++i) {
      if (seen[static_cast<int>(r.field)][i] == 0) {
        const std::string name = r.count == 1 ? r.name
                                 : r.field == Field::kMean
                                     ? std::string(1, "xyz"[i])
                                     : r.name + std::to_string(i);
        throw InputError(path + ": missing vertex property '" + name + "'");
      }
    }
  }
  const int num_rest = seen_rest.size();
  layout.sh_degree = -1;
  for (int d = 0; d <= kMaxShDegree; ++d)
    if (num_rest == 3 * (NumShCoeffs(d) - 1)) layout.sh_degree = d;
  if (layout.sh_degree < 0)
    throw InputError(path + ": " + std::to_string(num_rest) +
                     " f_rest properties; expected 0, 9, 24 or 45");
  std::vector<bool> rest_present(num_rest, false);
  for (int j : seen_rest) {
    if (j >= num_rest || rest_present[j])
      throw InputError(path + ": f_rest_" + std::to_string(j) +
                       " is duplicated or out of range for " +
                       std::to_string(num_rest) + " f_rest properties");
    rest_present[j] = true;
  }
  return layout;
}

// Tools that store opacity in 8 bits write opacity 1 and 0 back as logits
// +Inf and -Inf. The largest finite logit we keep, that of opacity 0.9999,
// renders exactly as opacity 1 (alpha saturates at 0.99) and its negative
// exactly as 0 (alpha below 1/255 is skipped), yet leaves a gradient if the
// model is trained further.
const double kOpacityLogitLimit = std::log(9999.0);

// The one place a vertex value is accepted or rejected: the model never
// holds a NaN or an infinity. Infinite opacity logits are clamped to
// +/-kOpacityLogitLimit and counted in *clamped (for one warning).
double AcceptedValue(const std::string& path, int64_t vertex, const Target& t,
                     double v, int64_t* clamped) {
  if (t.field == Field::kOpacity && std::isinf(v)) {
    ++*clamped;
    return v > 0 ? kOpacityLogitLimit : -kOpacityLogitLimit;
  }
  if (!std::isfinite(v))
    throw InputError(path + ": vertex " + std::to_string(vertex) +
                     " has a non-finite value");
  return v;
}

// Stores value v of vertex n where target t says.
void Store(const Target& t, int64_t n, double v, GaussianSet* g) {
  const int k_count = g->sh_coeffs();
  switch (t.field) {
    case Field::kMean:
      g->means[3 * n + t.index] = v;
      break;
    case Field::kShDc:
      g->sh[(n * k_count) * 3 + t.index] = v;
      break;
    case Field::kShRest: {
      // Channel-major: all R coefficients first, then G, then B.
      const int c = t.index / (k_count - 1);
      const int k = 1 + t.index % (k_count - 1);
      g->sh[(n * k_count + k) * 3 + c] = v;
      break;
    }
    case Field::kOpacity:
      g->opacity_logits[n] = v;
      break;
    case Field::kScale:
      g->log_scales[3 * n + t.index] = v;
      break;
    case Field::kRot:
      g->quats[4 * n + t.index] = v;
      break;
    case Field::kDynamic:
      g->dynamic_logits[n] = v;
      break;
    case Field::kIgnored:
      break;
  }
}

}  // namespace

GaussianSet ReadPly(const std::string& path) {
  const std::string data = ReadWholeFile(path);
  const PlyHeader header = ParseHeader(path, data);
  const int vertex_index = VertexElementIndex(path, header);
  const PlyElement& vertex = header.elements[vertex_index];
  const VertexLayout layout = MapVertexProperties(path, vertex);
  CheckSizeFits(path, data, header, vertex_index);

  GaussianSet g;
  g.sh_degree = layout.sh_degree;
  g.Resize(static_cast<int>(vertex.count));
  RowReader reader(path, data, header);
  for (int e = 0; e < vertex_index; ++e) reader.Skip(header.elements[e]);
  std::vector<double> values;
  int64_t clamped = 0;
  for (int64_t n = 0; n < vertex.count; ++n) {
    reader.Read(vertex, n, &values);
    for (size_t p = 0; p < layout.targets.size(); ++p) {
      const Target& t = layout.targets[p];
      if (t.field == Field::kIgnored) continue;
      Store(t, n, AcceptedValue(path, n, t, values[p], &clamped), &g);
    }
  }
  if (clamped > 0) {
    LOG(WARNING) << path << ": " << clamped
                 << " opacity logits are +/-Inf (opacity exactly 1 or 0, as "
                    "8-bit formats write them back); clamped to +/-"
                 << kOpacityLogitLimit;
  }
  return g;
}

std::string EncodePly(const GaussianSet& gaussians) {
  gaussians.CheckConsistent();
  const int n = gaussians.size();
  const int k_count = gaussians.sh_coeffs();
  const int num_rest = 3 * (k_count - 1);

  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\nelement vertex " << n
         << "\n";
  std::vector<std::string> names = {"x",  "y",      "z",      "nx",    "ny",
                                    "nz", "f_dc_0", "f_dc_1", "f_dc_2"};
  for (int j = 0; j < num_rest; ++j)
    names.push_back("f_rest_" + std::to_string(j));
  for (const char* name : {"opacity", "scale_0", "scale_1", "scale_2", "rot_0",
                           "rot_1", "rot_2", "rot_3", "dynamic_logit"})
    names.push_back(name);
  for (const std::string& name : names)
    header << "property float " << name << "\n";
  header << "end_header\n";

  const size_t stride = names.size();
  std::vector<float> body(stride * n);
  for (int i = 0; i < n; ++i) {
    float* row = body.data() + stride * i;
    for (int a = 0; a < 3; ++a) row[a] = gaussians.means[3 * i + a];
    row[3] = row[4] = row[5] = 0.0f;  // normals, unused by 3DGS tools
    for (int c = 0; c < 3; ++c)
      row[6 + c] = gaussians.sh[(i * k_count) * 3 + c];
    for (int j = 0; j < num_rest; ++j) {
      const int c = j / (k_count - 1);
      const int k = 1 + j % (k_count - 1);
      row[9 + j] = gaussians.sh[(i * k_count + k) * 3 + c];
    }
    float* tail = row + 9 + num_rest;
    tail[0] = gaussians.opacity_logits[i];
    for (int a = 0; a < 3; ++a) tail[1 + a] = gaussians.log_scales[3 * i + a];
    for (int a = 0; a < 4; ++a) tail[4 + a] = gaussians.quats[4 * i + a];
    tail[8] = gaussians.dynamic_logits[i];
  }

  std::string bytes = header.str();
  bytes.append(reinterpret_cast<const char*>(body.data()),
               body.size() * sizeof(float));
  return bytes;
}

void WritePly(const GaussianSet& gaussians, const std::string& path) {
  const std::string bytes = EncodePly(gaussians);
  WriteFileAtomically(path, [&bytes](std::ofstream& file) {
    file.write(bytes.data(), bytes.size());
  });
}

}  // namespace es
