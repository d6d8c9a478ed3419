#include "core/loop/loop_model.h"

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/base/input_error.h"
#include "tests/expect_error.h"
#include "tests/expect_same_gaussians.h"
#include "tests/temp_dir_test.h"

namespace es {
namespace {

namespace fs = std::filesystem;

class LoopModelTest : public TempDirTest {};

// Values exactly representable in float32, so the PLY round trip is exact.
LoopModel SmallModel() {
  LoopModel m;
  m.cycle_length = 5;
  GaussianSet& g = m.gaussians;
  g.sh_degree = 2;
  g.Resize(9);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  for (auto* v : {&g.means, &g.log_scales, &g.quats, &g.opacity_logits,
                  &g.sh, &g.dynamic_logits})
    for (double& x : *v) x = u(rng);
  m.dynamic_index = {0, 3, 4, 8};
  m.start_times = {4, 0, 2, 1};
  MotionFieldOptions mo;
  mo.triplane.resolution = 4;
  mo.triplane.channels = 2;
  mo.mlp_width = 8;
  m.motion.emplace(mo);
  m.motion->SetBox({-2, -2, -2}, {2, 2, 3});
  ResidualFieldOptions ro;
  ro.triplane.resolution = 4;
  ro.triplane.channels = 2;
  ro.cycle_length = 5;
  ro.mlp_width = 8;
  m.residual.emplace(ro);
  m.residual->SetBox({-2, -2, -2}, {2, 2, 3});
  return m;
}

void ExpectSameParams(const FieldParams& a, const FieldParams& b,
                      const Triplane& triplane, const Mlp& mlp) {
  for (int i = 0; i < triplane.num_params(); ++i)
    ASSERT_EQ(a.triplane[i], b.triplane[i]) << "triplane " << i;
  for (int i = 0; i < mlp.num_params(); ++i)
    ASSERT_EQ(a.mlp[i], b.mlp[i]) << "mlp " << i;
}

void ExpectSame(const LoopModel& a, const LoopModel& b) {
  EXPECT_EQ(a.cycle_length, b.cycle_length);
  EXPECT_EQ(a.dynamic_index, b.dynamic_index);
  EXPECT_EQ(a.start_times, b.start_times);
  ExpectSameGaussians(a.gaussians, b.gaussians);
  ASSERT_EQ(a.motion.has_value(), b.motion.has_value());
  ASSERT_EQ(a.residual.has_value(), b.residual.has_value());
  if (a.motion) {
    ExpectSameParams(a.motion->params(), b.motion->params(),
                     a.motion->triplane(), a.motion->mlp());
    EXPECT_EQ(a.motion->triplane().box_min(), b.motion->triplane().box_min());
    EXPECT_EQ(a.motion->triplane().box_max(), b.motion->triplane().box_max());
  }
  if (a.residual) {
    ExpectSameParams(a.residual->params(), b.residual->params(),
                     a.residual->triplane(), a.residual->mlp());
    EXPECT_EQ(a.residual->triplane().box_min(),
              b.residual->triplane().box_min());
    EXPECT_EQ(a.residual->options().cycle_length,
              b.residual->options().cycle_length);
  }
}

TEST_F(LoopModelTest, SaveLoadRoundTripIsIdentical) {
  const LoopModel m = SmallModel();
  SaveLoopModel(m, dir_.string());
  for (const char* f : {"canonical.ply", "loop.txt", "motion_field.bin",
                        "residual_field.bin"})
    EXPECT_TRUE(fs::exists(Path(f))) << f;
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  const LoopModel loaded = LoadLoopModel(dir_.string());
  ExpectSame(m, loaded);
  // Saving what was loaded gives the same bytes.
  const fs::path again = dir_ / "again";
  SaveLoopModel(loaded, again.string());
  ExpectSame(loaded, LoadLoopModel(again.string()));
}

TEST_F(LoopModelTest, AbsentFieldsStayAbsent) {
  LoopModel m = SmallModel();
  SaveLoopModel(m, dir_.string());
  m.motion.reset();
  m.residual.reset();
  m.dynamic_index.clear();
  m.start_times.clear();
  // Overwriting with a field-less model drops the old field files.
  SaveLoopModel(m, dir_.string());
  const LoopModel loaded = LoadLoopModel(dir_.string());
  ExpectSame(m, loaded);
  EXPECT_FALSE(loaded.motion.has_value());
  EXPECT_FALSE(loaded.residual.has_value());
}

void ExpectInputError(const std::string& dir, const std::string& file,
                      const std::string& what) {
  ExpectErrorNaming<InputError>([&] { LoadLoopModel(dir); }, {file, what});
}

TEST_F(LoopModelTest, BadLoopFilesAreRejected) {
  SaveLoopModel(SmallModel(), dir_.string());
  const std::string loop = Path("loop.txt");
  auto write = [&loop](const std::string& text) {
    std::ofstream(loop) << text;
  };
  write("cycle_length 5\nnum_dynamic 2\n0 1\n9 0\n");
  ExpectInputError(dir_.string(), loop, "out of range");
  write("cycle_length 5\nnum_dynamic 2\n3 1\n2 0\n");
  ExpectInputError(dir_.string(), loop, "not ascending");
  write("cycle_length 5\nnum_dynamic 2\n0 1\n2 5\n");
  ExpectInputError(dir_.string(), loop, "start time 5");
  write("cycle_length 5\nnum_dynamic 3\n0 1\n2 4\n");
  ExpectInputError(dir_.string(), loop, "expected 3");
  write("cycle 5\n");
  ExpectInputError(dir_.string(), loop, "cycle_length");
  write("cycle_length 6\nnum_dynamic 1\n0 1\n");
  ExpectInputError(dir_.string(), Path("residual_field.bin"), "cycle length");
  fs::remove(loop);
  ExpectInputError(dir_.string(), loop, "cannot open");
  fs::remove(Path("canonical.ply"));
  ExpectInputError(dir_.string(), Path("canonical.ply"), "");
}

TEST_F(LoopModelTest, BadFieldFileIsRejectedNamingIt) {
  SaveLoopModel(SmallModel(), dir_.string());
  const std::string motion = Path("motion_field.bin");
  fs::resize_file(motion, fs::file_size(motion) - 8);
  ExpectInputError(dir_.string(), motion, "truncated");
}

}  // namespace
}  // namespace es
