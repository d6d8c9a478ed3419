#include "core/io/ply_io.h"

#include <glog/logging.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/base/input_error.h"
#include "tests/expect_error.h"
#include "tests/expect_same_gaussians.h"
#include "tests/temp_dir_test.h"
#include "tests/whole_file.h"

using ::testing::HasSubstr;

namespace es {
namespace {

namespace fs = std::filesystem;

class PlyIoTest : public TempDirTest {};

// Random Gaussians whose values are exactly representable in float32.
GaussianSet RandomGaussians(int n, int degree, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  GaussianSet g;
  g.sh_degree = degree;
  g.Resize(n);
  for (auto* v : {&g.means, &g.log_scales, &g.quats, &g.opacity_logits, &g.sh,
                  &g.dynamic_logits})
    for (double& x : *v) x = u(rng);
  return g;
}

TEST_F(PlyIoTest, RoundTripIsBitExactForEveryShDegree) {
  for (int degree = 0; degree <= kMaxShDegree; ++degree) {
    const GaussianSet g = RandomGaussians(17, degree, 100 + degree);
    const std::string path = Path("g" + std::to_string(degree) + ".ply");
    WritePly(g, path);
    ExpectSameGaussians(ReadPly(path), g);
  }
}

TEST_F(PlyIoTest, EmptySetRoundTrips) {
  GaussianSet g;
  g.sh_degree = 2;
  WritePly(g, Path("empty.ply"));
  const GaussianSet read = ReadPly(Path("empty.ply"));
  EXPECT_EQ(read.size(), 0);
  EXPECT_EQ(read.sh_degree, 2);
}

// Builds a PLY the way other 3DGS tools write it: the standard property
// order with normals, plus properties we do not know, and f_rest stored
// channel-major. Value of property p of vertex n is Value(n, p).
struct StandardPly {
  std::vector<std::string> names;
  int num_vertices = 2;
  static constexpr int kDegree = 1;  // 9 f_rest

  StandardPly() {
    for (const char* name :
         {"x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"})
      names.push_back(name);
    names.push_back("red");  // unknown, between known ones
    for (int j = 0; j < 9; ++j) names.push_back("f_rest_" + std::to_string(j));
    for (const char* name : {"opacity", "scale_0", "scale_1", "scale_2",
                             "rot_0", "rot_1", "rot_2", "rot_3", "extra_x"})
      names.push_back(name);
  }

  static double Value(int n, int p) { return 0.25 * (100 * n + p) - 7.0; }
  int Index(const std::string& name) const {
    return std::find(names.begin(), names.end(), name) - names.begin();
  }

  std::string Header(const std::string& format) const {
    std::string h = "ply\nformat " + format +
                    " 1.0\ncomment written by a test\n"
                    "element vertex " +
                    std::to_string(num_vertices) + "\n";
    for (const std::string& name : names) {
      // "red" as uchar, the rest as float or double, to exercise conversion.
      const char* type = name == "red"       ? "uchar"
                         : name == "opacity" ? "double"
                                             : "float";
      h += std::string("property ") + type + " " + name + "\n";
    }
    return h +
           "element face 1\nproperty list uchar int vertex_indices\n"
           "end_header\n";
  }

  void WriteBinary(const std::string& path) const {
    std::ofstream f(path, std::ios::binary);
    f << Header("binary_little_endian");
    for (int n = 0; n < num_vertices; ++n) {
      for (size_t p = 0; p < names.size(); ++p) {
        if (names[p] == "red") {
          const uint8_t v = 200;
          f.write(reinterpret_cast<const char*>(&v), 1);
        } else if (names[p] == "opacity") {
          const double v = Value(n, p);
          f.write(reinterpret_cast<const char*>(&v), 8);
        } else {
          const float v = Value(n, p);
          f.write(reinterpret_cast<const char*>(&v), 4);
        }
      }
    }
    const uint8_t count = 3;
    const int32_t face[3] = {0, 1, 0};
    f.write(reinterpret_cast<const char*>(&count), 1);
    f.write(reinterpret_cast<const char*>(face), sizeof(face));
  }

  void WriteAscii(const std::string& path) const {
    std::ofstream f(path);
    f << Header("ascii");
    for (int n = 0; n < num_vertices; ++n) {
      for (size_t p = 0; p < names.size(); ++p)
        f << (names[p] == "red" ? 200.0 : Value(n, p)) << ' ';
      f << "\n";
    }
    f << "3 0 1 0\n";
  }

  void ExpectMatches(const GaussianSet& g) const {
    ASSERT_EQ(g.size(), num_vertices);
    ASSERT_EQ(g.sh_degree, kDegree);
    const int k_count = 4;
    for (int n = 0; n < num_vertices; ++n) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(g.means[3 * n + a], Value(n, a));
        EXPECT_EQ(g.log_scales[3 * n + a],
                  Value(n, Index("scale_" + std::to_string(a))));
        EXPECT_EQ(g.sh[(n * k_count) * 3 + a],
                  Value(n, Index("f_dc_" + std::to_string(a))));
      }
      for (int a = 0; a < 4; ++a)
        EXPECT_EQ(g.quats[4 * n + a],
                  Value(n, Index("rot_" + std::to_string(a))));
      EXPECT_EQ(g.opacity_logits[n], Value(n, Index("opacity")));
      EXPECT_EQ(g.dynamic_logits[n], 0.0);
      // Channel-major: f_rest_0..2 are red k = 1..3, f_rest_3..5 green, ...
      for (int c = 0; c < 3; ++c)
        for (int k = 1; k < k_count; ++k)
          EXPECT_EQ(g.sh[(n * k_count + k) * 3 + c],
                    Value(n, Index("f_rest_" +
                                   std::to_string(c * (k_count - 1) + k - 1))))
              << "n=" << n << " c=" << c << " k=" << k;
    }
  }
};

TEST_F(PlyIoTest, ReadsStandardBinaryLayoutWithUnknownProperties) {
  const StandardPly ply;
  ply.WriteBinary(Path("std.ply"));
  ply.ExpectMatches(ReadPly(Path("std.ply")));
}

TEST_F(PlyIoTest, ReadsAsciiLayout) {
  const StandardPly ply;
  ply.WriteAscii(Path("ascii.ply"));
  ply.ExpectMatches(ReadPly(Path("ascii.ply")));
}

TEST_F(PlyIoTest, WrittenFileHasStandardHeader) {
  WritePly(RandomGaussians(3, 1, 7), Path("h.ply"));
  std::ifstream f(Path("h.ply"), std::ios::binary);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(f, line) && line != "end_header") lines.push_back(line);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0], "ply");
  EXPECT_EQ(lines[1], "format binary_little_endian 1.0");
  EXPECT_EQ(lines[2], "element vertex 3");
  const std::vector<std::string> expected_start = {
      "property float x",      "property float y",
      "property float z",      "property float nx",
      "property float ny",     "property float nz",
      "property float f_dc_0", "property float f_dc_1",
      "property float f_dc_2", "property float f_rest_0"};
  for (size_t i = 0; i < expected_start.size(); ++i)
    EXPECT_EQ(lines[3 + i], expected_start[i]);
  EXPECT_EQ(lines.back(), "property float dynamic_logit");
  EXPECT_EQ(lines.size(), 3u + 9 + 9 + 1 + 3 + 4 + 1);
}

// Every bad input throws InputError naming the file.
void ExpectInputErrorNaming(const std::string& path,
                            const std::string& detail) {
  SCOPED_TRACE(detail);
  ExpectErrorNaming<InputError>([&] { ReadPly(path); }, {path});
}


// The ASCII file of `ply` with one more element before the vertices: its
// header lines `declaration`, and its rows `rows` first in the data.
std::string WithElementFirst(const StandardPly& ply, const std::string& path,
                             const std::string& declaration,
                             const std::string& rows) {
  ply.WriteAscii(path);
  std::string text = ReadWholeFile(path);
  text.insert(text.find("element vertex"), declaration);
  text.insert(text.find("end_header\n") + 11, rows);
  return text;
}

TEST_F(PlyIoTest, MissingFileNamesIt) {
  ExpectInputErrorNaming(Path("nope.ply"), "missing file");
}

TEST_F(PlyIoTest, MissingPropertyNamesFile) {
  StandardPly ply;
  ply.names.erase(ply.names.begin() + ply.Index("rot_2"));
  ply.WriteBinary(Path("norot.ply"));
  ExpectInputErrorNaming(Path("norot.ply"), "missing rot_2");
}

TEST_F(PlyIoTest, BadRestCountNamesFile) {
  StandardPly ply;
  ply.names.erase(ply.names.begin() + ply.Index("f_rest_8"));
  ply.WriteBinary(Path("rest8.ply"));
  ExpectInputErrorNaming(Path("rest8.ply"), "8 f_rest");
}

TEST_F(PlyIoTest, TruncatedFileNamesIt) {
  WritePly(RandomGaussians(5, 2, 3), Path("full.ply"));
  const std::string full = ReadWholeFile(Path("full.ply"));
  WriteWholeFile(Path("cut.ply"), full.substr(0, full.size() - 4));
  ExpectInputErrorNaming(Path("cut.ply"), "truncated body");
  WriteWholeFile(Path("cut_header.ply"), full.substr(0, full.find("end_header")));
  ExpectInputErrorNaming(Path("cut_header.ply"), "truncated header");
}

TEST_F(PlyIoTest, NonFiniteValueNamesFile) {
  const float kInf = std::numeric_limits<float>::infinity();
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), kInf}) {
    GaussianSet g = RandomGaussians(4, 0, 5);
    g.means[7] = bad;
    WritePly(g, Path("nan.ply"));
    ExpectInputErrorNaming(Path("nan.ply"), "non-finite");
  }
  GaussianSet g = RandomGaussians(4, 0, 5);
  g.opacity_logits[2] = std::numeric_limits<float>::quiet_NaN();
  WritePly(g, Path("nan_opacity.ply"));
  ExpectInputErrorNaming(Path("nan_opacity.ply"), "non-finite");
}

// Collects the WARNING lines glog emits while it is alive.
class WarningCollector : public google::LogSink {
 public:
  WarningCollector() { google::AddLogSink(this); }
  ~WarningCollector() override { google::RemoveLogSink(this); }
  void send(google::LogSeverity severity, const char*, const char*, int,
            const struct ::tm*, const char* message, size_t size) override {
    if (severity == google::GLOG_WARNING) lines.emplace_back(message, size);
  }
  std::vector<std::string> lines;
};

TEST_F(PlyIoTest, InfiniteOpacityIsClampedToRenderTheSame) {
  const float kInf = std::numeric_limits<float>::infinity();
  GaussianSet g = RandomGaussians(6, 1, 9);
  g.opacity_logits = {1.5, kInf, -2.0, -kInf, 0.25, kInf};
  WritePly(g, Path("inf.ply"));
  WarningCollector warnings;
  const GaussianSet read = ReadPly(Path("inf.ply"));
  const double limit = std::log(9999.0);
  EXPECT_EQ(read.opacity_logits,
            std::vector<double>({1.5, limit, -2.0, -limit, 0.25, limit}));
  EXPECT_EQ(read.means, g.means);
  // Opacity 0.9999 saturates alpha as 1 does; 0.0001 is skipped as 0 is.
  EXPECT_GT(Sigmoid(limit), 0.99);
  EXPECT_LT(Sigmoid(-limit), 1.0 / 255);
  ASSERT_EQ(warnings.lines.size(), 1u);
  EXPECT_THAT(warnings.lines[0], HasSubstr(Path("inf.ply")));
  EXPECT_THAT(warnings.lines[0], HasSubstr(" 3 "));
}

TEST_F(PlyIoTest, BadHeaderNamesFile) {
  WriteWholeFile(Path("notply.ply"), "hello\nend_header\n");
  ExpectInputErrorNaming(Path("notply.ply"), "no magic");
  WriteWholeFile(Path("bigendian.ply"),
                 "ply\nformat binary_big_endian 1.0\nelement vertex 0\n"
                 "end_header\n");
  ExpectInputErrorNaming(Path("bigendian.ply"), "big endian");
  WriteWholeFile(Path("novertex.ply"),
                 "ply\nformat ascii 1.0\nelement face 0\nend_header\n");
  ExpectInputErrorNaming(Path("novertex.ply"), "no vertex element");
}

// Fuzzer finding (D1): an element without properties announcing 9e18 rows
// before the vertices occupies no bytes; the reader used to loop over every
// empty row and never return.
TEST_F(PlyIoTest, HugeElementWithoutPropertiesIsSkipped) {
  StandardPly ply;
  ply.num_vertices = 1;
  WriteWholeFile(Path("junk.ply"),
                 WithElementFirst(ply, Path("base.ply"),
                                  "element junk 9000000000000000000\n", ""));
  EXPECT_EQ(ReadPly(Path("junk.ply")).size(), 1);

  WriteWholeFile(
      Path("junk0.ply"),
      "ply\nformat ascii 1.0\nelement junk 9000000000000000000\n"
      "element vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nproperty float f_dc_0\nproperty float f_dc_1\n"
      "property float f_dc_2\nproperty float opacity\n"
      "property float scale_0\nproperty float scale_1\n"
      "property float scale_2\nproperty float rot_0\n"
      "property float rot_1\nproperty float rot_2\n"
      "property float rot_3\nend_header\n");
  EXPECT_EQ(ReadPly(Path("junk0.ply")).size(), 0);
}

// Fuzzer finding (D7): a list length stored as a float that is NaN, Inf,
// negative, fractional or larger than the file was cast to an integer
// (undefined behaviour, or a loop over 9e18 items); each is now a bad-file
// error naming the file.
TEST_F(PlyIoTest, BadFloatListLengthIsAnInputError) {
  StandardPly ply;
  ply.num_vertices = 1;
  for (const char* length : {"nan", "inf", "-inf", "-1", "1.5", "1e300"}) {
    WriteWholeFile(Path("list.ply"),
                   WithElementFirst(ply, Path("base.ply"),
                                    "element f 1\nproperty list float int i\n",
                                    std::string(length) + " 7\n"));
    ExpectInputErrorNaming(Path("list.ply"), length);
  }
  // Binary: a float32 NaN length.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement f 1\n"
      "property list float int i\nend_header\n";
  binary.append(reinterpret_cast<const char*>(&nan), sizeof(nan));
  WriteWholeFile(Path("list_binary.ply"), binary);
  ExpectInputErrorNaming(Path("list_binary.ply"), "binary NaN length");
}

// A list of a plausible length is still read and skipped.
TEST_F(PlyIoTest, FloatListLengthThatIsWholeIsRead) {
  StandardPly ply;
  ply.num_vertices = 2;
  WriteWholeFile(Path("list.ply"),
                 WithElementFirst(ply, Path("base.ply"),
                                  "element f 2\nproperty list float int i\n",
                                  "2 7 8\n0\n"));
  ply.ExpectMatches(ReadPly(Path("list.ply")));
}

}  // namespace
}  // namespace es
