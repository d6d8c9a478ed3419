// Every binary and script as a new user meets them: --help lists the tool's
// own flags first and exits 0, --version names the commit, and each bad
// flag value is refused before any work with a message that names the flag,
// exit status 1 and no stack trace. Runs the built binaries (ES_BINARY_DIR)
// on a tiny synthetic scene; a few seconds in all.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/pipeline_test_util.h"

#ifdef ES_HAVE_CUDA
#include "core/base/cuda/cuda_error.h"
#endif

using ::testing::HasSubstr;
using ::testing::Not;

namespace {

namespace fs = std::filesystem;

const fs::path kScripts = fs::path(ES_SOURCE_DIR) / "scripts";

using es::CommandResult;
using es::kBin;
using es::RunCommand;

const std::vector<std::string> kApps = {
    "es_static", "es_flowinit", "es_train",     "es_animate",
    "es_eval",   "es_render",   "es_synth",     "es_contact_sheet",
    "es_plot",   "eulersplat",  "bench_static", "es_export",
    "es_compare"};

class CliTest : public ::testing::Test {
 protected:
  // One tiny scene (8 frames) for the checks that need a real scene.
  static void SetUpTestSuite() {
    // One folder per process: ctest runs each test of this suite as its own
    // process, in parallel, and a shared folder was wiped under a neighbour.
    root_ = fs::path(ES_BINARY_DIR) /
            ("cli_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    scene_ = root_ / "scene";
    const CommandResult r =
        RunCommand((kBin / "es_synth").string() + " --out " + scene_.string() +
                   " --frames 8 --width 32 --height 24 --detail 0.02"
                   " --num_points 50");
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }

  // Runs a binary that must refuse its flags: exit 1, a message containing
  // `expected`, and no CHECK failure or stack trace.
  static void ExpectRefused(const std::string& binary, const std::string& args,
                            const std::string& expected) {
    const CommandResult r = RunCommand((kBin / binary).string() + " " + args);
    EXPECT_EQ(r.status, 1) << binary << " " << args << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(expected))
        << binary << " " << args << "\nwanted: " << expected << "\ngot:\n"
        << r.output;
    EXPECT_THAT(r.output, Not(HasSubstr("Check failed")));
    EXPECT_THAT(r.output, Not(HasSubstr("stack trace")));
  }

  static fs::path root_, scene_;
};

fs::path CliTest::root_, CliTest::scene_;

TEST_F(CliTest, HelpListsTheToolsOwnFlagsFirstAndExitsZero) {
  for (const std::string& app : kApps) {
    const CommandResult r = RunCommand((kBin / app).string() + " --help");
    EXPECT_EQ(r.status, 0) << app << "\n" << r.output;
    const size_t flags = r.output.find("\nFlags:\n  --");
    ASSERT_NE(flags, std::string::npos) << app << "\n" << r.output;
    // The usage text comes first, then the tool's own flags; glog's and
    // gflags' own flags only with --helpfull.
    EXPECT_LT(flags, 800u) << app;
    EXPECT_THAT(r.output, Not(HasSubstr("logtostderr"))) << app;
    EXPECT_THAT(r.output, Not(HasSubstr("flagfile"))) << app;
  }
  const CommandResult full =
      RunCommand((kBin / "es_train").string() + " --helpfull");
  EXPECT_EQ(full.status, 0);
  EXPECT_THAT(full.output, HasSubstr("logtostderr"));
  EXPECT_LT(full.output.find("--cycle_length"),
            full.output.find("logtostderr"));
  EXPECT_EQ(RunCommand((kBin / "es_eval").string() + " -h").status, 0);
}

TEST_F(CliTest, HelpShowsReadableDefaults) {
  const CommandResult r = RunCommand((kBin / "es_static").string() + " --help");
  // 2.5e-3 / 20, which gflags itself prints as 0.00012500000000000001.
  EXPECT_THAT(r.output, HasSubstr("--lr_sh_rest (double, default 0.000125)"));
  EXPECT_THAT(r.output, HasSubstr("--scene (string, default \"\")"));
  EXPECT_THAT(r.output, HasSubstr("--iterations (int32, default 10000)"));
  // Descriptions are wrapped to 80 columns.
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    EXPECT_LE(line.size(), 80u) << line;
  }
}

// Shared plumbing (apps/common, and benchmark_main.h for the Google
// Benchmark binaries): a few binaries stand for all.
TEST_F(CliTest, VersionNamesTheCommit) {
  const std::regex version(
      R"(eulersplat [0-9]+\.[0-9]+\.[0-9]+ \(commit ([0-9a-f]{12}|unknown)\)\n)");
  for (const std::string app :
       {"es_train", "eulersplat", "es_plot", "bench_looping"}) {
    const CommandResult r = RunCommand((kBin / app).string() + " --version");
    EXPECT_EQ(r.status, 0) << app;
    EXPECT_TRUE(std::regex_match(r.output, version)) << app << ": " << r.output;
  }
}

TEST_F(CliTest, NonFiniteOrNegativeLearningRatesAreRefused) {
  const std::string io =
      " --scene " + scene_.string() + " --out " + (root_ / "o").string();
  ExpectRefused("es_static", io + " --lr_opacity nan",
                "--lr_opacity=nan: must be a finite number");
  ExpectRefused("es_static", io + " --lr_position inf",
                "--lr_position=inf: must be a finite number");
  ExpectRefused("es_train", io + " --init x --lr_motion_mlp -1",
                "--lr_motion_mlp=-1: a learning rate must be >= 0");
  ExpectRefused("es_flowinit", io + " --lr_triplane -inf",
                "--lr_triplane=-inf: must be a finite number");
  ExpectRefused("es_animate", io + " --model m --fps nan",
                "--fps=nan: must be a finite number");
  EXPECT_FALSE(fs::exists(root_ / "o")) << "work started anyway";
}

TEST_F(CliTest, OutOfRangeValuesAreRefusedBeforeAnyWork) {
  const std::string scene = " --scene " + scene_.string();
  const std::string out = (root_ / "o").string();
  const std::string io = scene + " --out " + out;  // eulersplat, es_static
  const std::string train = scene + " --init x --out " + out;
  const std::string model = scene + " --model m --out " + out;
  // Binary, arguments, what the refusal must say.
  const std::vector<std::array<std::string, 3>> refusals = {
      {"eulersplat", io + " --static_iterations -5",
       "--static_iterations=-5: must be >= 1"},
      {"eulersplat", io + " --joint_iterations -2",
       "--joint_iterations=-2: must be >= 0"},
      {"es_train", train + " --dynamic_threshold 1.5",
       "--dynamic_threshold=1.5: must be in (0, 1)"},
      {"es_train", train + " --flow_prior_weight -1",
       "--flow_prior_weight=-1: must be >= 0"},
      {"es_train", train + " --densify_water_growth 0.5",
       "--densify_water_growth=0.5: must be in [1, 1000]"},
      {"es_train", train + " --input_cache_mb -1",
       "--input_cache_mb=-1: must be >= 0"},
      {"es_train", train + " --residual_precision half",
       "unknown --residual_precision 'half'; available: double, float"},
      {"es_static", io + " --iterations 0", "--iterations must be positive"},
      {"es_static", io + " --max_world_scale -0.1",
       "--max_world_scale must be >= 0 and finite (0: off)"},
      {"es_animate", model + " --track_count -3",
       "--track_count=-3: must be >= 1"},
      {"es_animate", model + " --xt_slice middle --camera fixed", ""},
      {"es_flowinit", scene + " --stride 0", "--stride=0: must be >= 1"},
      {"es_flowinit", scene + " --frame_gap 0", "--frame_gap=0: must be >= 1"},
      {"es_eval", model + " --seam_cycles 1", "--seam_cycles must be >= 2"},
      {"es_eval", model + " --realism_patches 8",
       "--realism_patches=8: must be >= 16"},
      {"es_compare",
       "--scene s --other o --out " + out + " --realism_water_margin 0.9",
       "--realism_water_margin=0.9"},
      {"es_render", "--ply p --sparse s --out_dir o --depth_scale 0",
       "--depth_scale must be positive"},
      {"es_plot", "--history h.csv --out o --width 10",
       "--width=10: must be >= 200"},
      {"es_synth", "--out " + out + " stray", "unexpected argument 'stray'"},
      {"es_train", "--scene", ""}};  // gflags: missing value
  for (const auto& [binary, args, message] : refusals)
    ExpectRefused(binary, args, message);
  EXPECT_FALSE(fs::exists(root_ / "o")) << "work started anyway";
}

// es_animate --device: an unknown value is named; cuda is refused where
// this build or machine cannot run it, and with --tracks (whose positions
// stay on the GPU) where it can, before any work.
TEST_F(CliTest, AnimateDeviceIsCheckedBeforeAnyWork) {
  const std::string args = " --scene " + scene_.string() +
                           " --model m --out " + (root_ / "o").string();
  ExpectRefused("es_animate", args + " --device gpu",
                "--device must be cpu or cuda, not 'gpu'");
#ifdef ES_HAVE_CUDA
  std::string why;
  const std::string refusal = es::cuda::CudaDeviceAvailable(&why)
                                  ? "--tracks needs --device cpu"
                                  : "no CUDA device found";
#else
  const std::string refusal = "this build has no CUDA backend";
#endif
  ExpectRefused("es_animate", args + " --device cuda --tracks", refusal);
  EXPECT_FALSE(fs::exists(root_ / "o")) << "work started anyway";
}

// es_eval and the driver --device: an unknown value is named, and cuda is
// refused where this build or machine cannot run it, before any work (the
// driver before any stage runs).
TEST_F(CliTest, EvalAndDriverDeviceIsCheckedBeforeAnyWork) {
  const std::string out = (root_ / "o").string();
  const std::string scene = " --scene " + scene_.string();
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"es_eval", scene + " --model m --out " + out},
      {"eulersplat", scene + " --out " + out}};
  for (const auto& [binary, args] : commands) {
    ExpectRefused(binary, args + " --device gpu",
                  "--device must be cpu or cuda, not 'gpu'");
  }
#ifdef ES_HAVE_CUDA
  std::string why;
  if (es::cuda::CudaDeviceAvailable(&why)) {
    GTEST_SKIP() << "a CUDA device is present (" << why
                 << "): --device cuda is not refused here";
  }
  const std::string refusal = "--device cuda: no CUDA device found";
#else
  const std::string refusal = "--device cuda: this build has no CUDA backend";
#endif
  for (const auto& [binary, args] : commands) {
    ExpectRefused(binary, args + " --device cuda", refusal);
  }
  EXPECT_FALSE(fs::exists(root_ / "o")) << "work started anyway";
}

// es_flowinit --device: an unknown value is named; cuda is refused where
// this build or machine cannot run it, and with a Ceres solver (the device
// fits with Adam only) where it can, before the optical flow is computed.
TEST_F(CliTest, FlowinitDeviceIsCheckedBeforeAnyWork) {
  const std::string args =
      " --scene " + scene_.string() + " --out " + (root_ / "o").string();
  ExpectRefused("es_flowinit", args + " --device gpu",
                "--device must be cpu or cuda, not 'gpu'");
#ifdef ES_HAVE_CUDA
  std::string why;
  const std::string refusal =
      es::cuda::CudaDeviceAvailable(&why)
          ? "--device cuda pretrains with --solver adam only"
          : "no CUDA device found";
#else
  const std::string refusal = "this build has no CUDA backend";
#endif
  ExpectRefused("es_flowinit", args + " --device cuda --solver lbfgs",
                refusal);
  EXPECT_FALSE(fs::exists(root_ / "o")) << "work started anyway";
}

// --oracle_velocity needs the scene's ground truth: a scene without gt/ (a
// real video's) is refused by name before any flow is computed.
TEST_F(CliTest, OracleVelocityNeedsGroundTruth) {
  const fs::path plain = root_ / "no_truth";
  fs::copy(scene_, plain, fs::copy_options::recursive);
  fs::remove_all(plain / "gt");
  ExpectRefused("es_flowinit",
                "--scene " + plain.string() + " --out " +
                    (root_ / "oracle").string() + " --oracle_velocity seen",
                "gt/velocity_grid.bin: missing; --oracle_velocity needs a "
                "synthetic scene");
  ExpectRefused("es_flowinit",
                "--scene " + scene_.string() + " --out " +
                    (root_ / "oracle").string() + " --oracle_velocity all",
                "--oracle_velocity must be none, seen or full, not 'all'");
  EXPECT_FALSE(fs::exists(root_ / "oracle")) << "work started anyway";
}

// The loop cannot be longer than the video (and its cost grows with L):
// es_train refuses it, and the driver before Stage 1 trains.
TEST_F(CliTest, CycleLengthLongerThanTheVideoIsRefused) {
  const std::string out = (root_ / "long_loop").string();
  ExpectRefused("es_train",
                "--scene " + scene_.string() + " --init missing --out " + out +
                    " --cycle_length 1000",
                "--cycle_length=1000: must be <= 8");
  ExpectRefused(
      "eulersplat",
      "--scene " + scene_.string() + " --out " + out + " --cycle_length 1000",
      "--cycle_length=1000: must be <= 8");
  EXPECT_FALSE(fs::exists(fs::path(out) / "static"));
}

TEST_F(CliTest, CompareRefusesAnotherVideoThatDoesNotMatch) {
  const fs::path shorter = root_ / "shorter";
  const CommandResult r =
      RunCommand((kBin / "es_synth").string() + " --out " + shorter.string() +
                 " --frames 6 --width 32 --height 24 --detail 0.02"
                 " --num_points 50");
  ASSERT_EQ(r.status, 0) << r.output;
  ExpectRefused("es_compare",
                "--scene " + scene_.string() + " --other " +
                    shorter.string() + " --out " + (root_ / "cmp").string(),
                shorter.string() + ": 6 frames, but " + scene_.string() +
                    " has 8");
  const fs::path seed = root_ / "other_seed";
  ASSERT_EQ(RunCommand((kBin / "es_synth").string() + " --out " +
                       seed.string() +
                       " --frames 8 --width 32 --height 24 --detail 0.02"
                       " --num_points 50 --seed 5")
                .status,
            0);
  ExpectRefused("es_compare",
                "--scene " + scene_.string() + " --other " + seed.string() +
                    " --out " + (root_ / "cmp").string(),
                "camera differs");
  // Another draw of the same water matches and is measured.
  const fs::path draw = root_ / "draw";
  ASSERT_EQ(
      RunCommand((kBin / "es_synth").string() + " --out " + draw.string() +
                 " --frames 8 --width 32 --height 24 --detail 0.02"
                 " --num_points 50 --water_seed 5")
          .status,
      0);
  const CommandResult ok = RunCommand(
      (kBin / "es_compare").string() + " --scene " + scene_.string() +
      " --other " + draw.string() + " --out " + (root_ / "cmp").string());
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(fs::exists(root_ / "cmp" / "compare.json"));
}

TEST_F(CliTest, UnwritableOutputIsRefusedBeforeTraining) {
  const fs::path file = root_ / "a_file";
  std::ofstream(file) << "not a directory";
  const std::string out = (file / "out").string();
  ExpectRefused(
      "es_static",
      "--scene " + scene_.string() + " --out " + out + " --iterations 5",
      "--out=" + out + ": cannot create the directory");
  ExpectRefused("es_train",
                "--scene " + scene_.string() + " --init x --out " + out,
                "--out=" + out + ": cannot create the directory");
  ExpectRefused("eulersplat", "--scene " + scene_.string() + " --out " + out,
                "--out=" + out + ": cannot create the directory");
}

// The tools that write one thing check where before any work: es_synth
// before generating (a 3000-frame scene would take minutes), es_render and
// es_export before reading their inputs (here missing, so reading first
// would fail on those instead).
TEST_F(CliTest, UnwritableOutputIsRefusedBeforeAnyWork) {
  const fs::path file = root_ / "plain_file";
  std::ofstream(file) << "not a directory";
  const std::string out = (file / "out").string();
  ExpectRefused("es_synth", "--out " + out + " --frames 3000",
                "--out=" + out + ": cannot create the directory");
  const std::string missing = (root_ / "missing").string();
  ExpectRefused("es_render",
                "--ply " + missing + ".ply --sparse " + missing +
                    " --out_dir " + out,
                "--out_dir=" + out + ": cannot create the directory");
  const std::string ply = out + "/frame.ply";
  ExpectRefused("es_export", "--model " + missing + " --ply " + ply,
                "--ply=" + ply + ": cannot create its directory " + out);
  ExpectRefused("es_export",
                "--model " + missing + " --web " + out + " --scene " +
                    scene_.string(),
                "--web=" + out + ": cannot create the directory");
  // A --ply that names a directory is refused, not overwritten.
  ExpectRefused("es_export", "--model " + missing + " --ply " + root_.string(),
                "--ply=" + root_.string() + ": is a directory");
  EXPECT_FALSE(fs::exists(out));
}

// Every script answers --help with its usage, exit 0 and no side effects:
// run from a copy of scripts/ in an empty folder, anything it built or
// wrote would show up there.
TEST_F(CliTest, ScriptsAnswerHelpWithoutSideEffects) {
  const fs::path sandbox = root_ / "sandbox";
  fs::create_directories(sandbox);
  fs::copy(kScripts, sandbox / "scripts", fs::copy_options::recursive);
  int scripts = 0;
  for (const auto& entry : fs::directory_iterator(sandbox / "scripts")) {
    const std::string name = entry.path().filename().string();
    const bool python = entry.path().extension() == ".py";
    if (entry.path().extension() != ".sh" && !python) continue;
    ++scripts;
    const CommandResult r =
        RunCommand(std::string(python ? "python3 " : "bash ") +
                   entry.path().string() + " --help");
    EXPECT_EQ(r.status, 0) << name << "\n" << r.output;
    EXPECT_GT(r.output.size(), 30u) << name;
    EXPECT_THAT(r.output, HasSubstr("scripts/" + name))
        << name << " --help does not show its usage line\n"
        << r.output;
  }
  EXPECT_GE(scripts, 6);
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(sandbox)) {
    left.push_back(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::vector<std::string>{"scripts"});
}

}  // namespace
