#include "core/fields/field_io.h"

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "tests/expect_error.h"
#include "tests/memory_limit.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;

class FieldIoTest : public TempDirTest {};

// Non-default options everywhere, so a field that drops one is caught.
MotionField SmallMotion() {
  MotionFieldOptions o;
  o.triplane.resolution = 6;
  o.triplane.channels = 3;
  o.triplane.combination = PlaneCombination::kConcat;
  o.triplane.init_noise = 0.2;
  o.mlp_width = 9;
  o.mlp_depth = 3;
  o.velocity_scale = 0.03;
  o.last_layer_init_scale = 0.5;
  o.seed = 17;
  MotionField f(o);
  f.SetBox({-1, -2, -3}, {4, 5, 6.5});
  return f;
}

ResidualField SmallResidual() {
  ResidualFieldOptions o;
  o.triplane.resolution = 5;
  o.triplane.channels = 2;
  o.triplane.combination = PlaneCombination::kSum;
  o.cycle_length = 7;
  o.t_frequencies = 3;
  o.p_frequencies = 2;
  o.max_cycles = 9;
  o.mlp_width = 11;
  o.mlp_depth = 1;
  o.position_scale = 0.05;
  o.seed = 23;
  ResidualField f(o);
  f.SetBox({0, 0, 0}, {1, 2, 3});
  return f;
}

void ExpectSameTriplane(const Triplane& a, const Triplane& b) {
  EXPECT_EQ(a.options().resolution, b.options().resolution);
  EXPECT_EQ(a.options().channels, b.options().channels);
  EXPECT_EQ(a.options().combination, b.options().combination);
  EXPECT_EQ(a.options().init_noise, b.options().init_noise);
  EXPECT_EQ(a.box_min(), b.box_min());
  EXPECT_EQ(a.box_max(), b.box_max());
}

TEST_F(FieldIoTest, MotionFieldRoundTripsExactly) {
  MotionField f = SmallMotion();
  SaveMotionField(f, Path("v.bin"));
  EXPECT_FALSE(fs::exists(Path("v.bin.tmp")));
  MotionField g = LoadMotionField(Path("v.bin"));
  ExpectSameTriplane(f.triplane(), g.triplane());
  EXPECT_EQ(f.options().mlp_width, g.options().mlp_width);
  EXPECT_EQ(f.options().mlp_depth, g.options().mlp_depth);
  EXPECT_EQ(f.options().velocity_scale, g.options().velocity_scale);
  EXPECT_EQ(f.output_scale(), g.output_scale());
  EXPECT_EQ(f.triplane_params(), g.triplane_params());
  EXPECT_EQ(f.mlp_params(), g.mlp_params());
  // Same field: same velocities.
  const double x[3] = {0.3, 1.1, -0.4};
  double va[3], vb[3];
  FieldWorkspace ws;
  f.Evaluate(f.params(), 1, x, va, &ws);
  g.Evaluate(g.params(), 1, x, vb, &ws);
  for (int j = 0; j < 3; ++j) EXPECT_EQ(va[j], vb[j]);
}

TEST_F(FieldIoTest, ResidualFieldRoundTripsExactly) {
  ResidualField f = SmallResidual();
  SaveResidualField(f, Path("d.bin"));
  ResidualField g = LoadResidualField(Path("d.bin"));
  ExpectSameTriplane(f.triplane(), g.triplane());
  EXPECT_EQ(f.options().cycle_length, g.options().cycle_length);
  EXPECT_EQ(f.options().t_frequencies, g.options().t_frequencies);
  EXPECT_EQ(f.options().p_frequencies, g.options().p_frequencies);
  EXPECT_EQ(f.options().max_cycles, g.options().max_cycles);
  EXPECT_EQ(f.options().mlp_width, g.options().mlp_width);
  EXPECT_EQ(f.options().mlp_depth, g.options().mlp_depth);
  EXPECT_EQ(f.options().position_scale, g.options().position_scale);
  EXPECT_EQ(f.triplane_params(), g.triplane_params());
  EXPECT_EQ(f.mlp_params(), g.mlp_params());
  const double x[3] = {0.5, 0.5, 2.0};
  const int t = 3, p = -1;
  double a[kResidualDim], b[kResidualDim];
  FieldWorkspace ws;
  f.Evaluate(f.params(), 1, x, &t, &p, a, &ws);
  g.Evaluate(g.params(), 1, x, &t, &p, b, &ws);
  for (int j = 0; j < kResidualDim; ++j) EXPECT_EQ(a[j], b[j]);
}

// The error names the file and says what is wrong.
template <typename F>
void ExpectInputError(F load, const std::string& path,
                      const std::string& what) {
  ExpectErrorNaming<InputError>([&] { load(path); }, {path, what});
}

TEST_F(FieldIoTest, TruncatedFilesAreRejected) {
  SaveMotionField(SmallMotion(), Path("v.bin"));
  SaveResidualField(SmallResidual(), Path("d.bin"));
  for (const char* name : {"v.bin", "d.bin"}) {
    const auto size = fs::file_size(Path(name));
    for (auto keep : {size - 1, size / 2, decltype(size){40}}) {
      fs::copy_file(Path(name), Path("cut.bin"),
                    fs::copy_options::overwrite_existing);
      fs::resize_file(Path("cut.bin"), keep);
      if (std::string(name) == "v.bin") {
        ExpectInputError([](const std::string& p) { LoadMotionField(p); },
                         Path("cut.bin"), "truncated");
      } else {
        ExpectInputError([](const std::string& p) { LoadResidualField(p); },
                         Path("cut.bin"), "truncated");
      }
    }
  }
}

TEST_F(FieldIoTest, WrongMagicAndWrongKindAreRejected) {
  {
    std::ofstream out(Path("junk.bin"), std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nend_header\n";
  }
  ExpectInputError([](const std::string& p) { LoadMotionField(p); },
                   Path("junk.bin"), "not a field file");
  ExpectInputError([](const std::string& p) { LoadResidualField(p); },
                   Path("junk.bin"), "not a field file");
  SaveResidualField(SmallResidual(), Path("d.bin"));
  ExpectInputError([](const std::string& p) { LoadMotionField(p); },
                   Path("d.bin"), "motion field");
  ExpectInputError([](const std::string& p) { LoadMotionField(p); },
                   Path("missing.bin"), "cannot open");
}

// D8 (fuzzer): a header announcing a 4096^2 x 1024 triplane (400 GB of
// parameters; the count also overflowed an int) or a 4096-wide, 64-deep MLP
// in a file of a few hundred bytes is rejected before the field allocates.
TEST_F(FieldIoTest, HugeOptionsAreRejectedBeforeAllocating) {
  SaveMotionField(SmallMotion(), Path("v.bin"));
  SaveResidualField(SmallResidual(), Path("d.bin"));
  const size_t motion_magic = 27, residual_magic = 29;
  auto patch = [&](const char* from, const char* to, size_t offset,
                   std::initializer_list<int32_t> values) {
    fs::copy_file(Path(from), Path(to), fs::copy_options::overwrite_existing);
    std::fstream f(Path(to), std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(offset);
    for (int32_t v : values) f.write(reinterpret_cast<const char*>(&v), 4);
  };
  // Triplane resolution and channels follow the magic.
  patch("v.bin", "huge_v.bin", motion_magic, {4096, 1024});
  patch("d.bin", "huge_d.bin", residual_magic, {4096, 1024});
  // Motion: triplane options (3 int32 + 1 double), then MLP width, depth.
  patch("v.bin", "wide_v.bin", motion_magic + 20, {4096, 64});
  for (const char* name : {"huge_v.bin", "wide_v.bin"}) {
    const std::string path = Path(name);
    EXPECT_TRUE(ThrowsInputErrorWithinMemory(
        [&path] { LoadMotionField(path); }))
        << name;
  }
  const std::string path = Path("huge_d.bin");
  EXPECT_TRUE(
      ThrowsInputErrorWithinMemory([&path] { LoadResidualField(path); }));
}

TEST_F(FieldIoTest, NonFiniteParametersAreRejected) {
  MotionField f = SmallMotion();
  f.mlp_params()[3] = std::numeric_limits<double>::quiet_NaN();
  SaveMotionField(f, Path("nan.bin"));
  ExpectInputError([](const std::string& p) { LoadMotionField(p); },
                   Path("nan.bin"), "non-finite");
}

}  // namespace
}  // namespace es
