// Crash-safe runs: a full disk keeps the last good file; es_static killed
// with SIGKILL mid-run resumes within one checkpoint interval and ends with
// the very files an uninterrupted run writes; the driver holds a lock on its
// output folder and its stage dies with it.

#include <dirent.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/base/atomic_file.h"
#include "core/base/input_error.h"
#include "core/fields/field_io.h"
#include "core/fields/motion_field.h"
#include "core/io/ply_io.h"
#include "solvers/checkpoint/checkpoint.h"
#include "solvers/pipeline/run_lock.h"
#include "tests/temp_dir_test.h"
#include "tests/whole_file.h"

using ::testing::HasSubstr;
using ::testing::Not;

namespace es {
namespace {

namespace fs = std::filesystem;

const fs::path kBin = fs::path(ES_BINARY_DIR) / "bin";

GaussianSet SomeGaussians(int n) {
  GaussianSet g;
  g.Resize(n);
  for (size_t i = 0; i < g.means.size(); ++i) g.means[i] = 0.01 * i;
  return g;
}

// A process started with its stdout (and stderr) on a pipe we read lines
// from.
class Process {
 public:
  explicit Process(const std::vector<std::string>& argv) {
    int fds[2];
    EXPECT_EQ(::pipe(fds), 0);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], 1);
      ::dup2(fds[1], 2);
      ::close(fds[0]);
      ::close(fds[1]);
      std::vector<char*> args;
      for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    out_ = ::fdopen(fds[0], "r");
  }
  ~Process() {
    if (out_ != nullptr) std::fclose(out_);
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }

  // Reads lines (appending them to log()) until one contains `text`; false
  // at end of output.
  bool WaitForLine(const std::string& text) {
    char line[4096];
    while (std::fgets(line, sizeof(line), out_) != nullptr) {
      log_ += line;
      if (std::string(line).find(text) != std::string::npos) return true;
    }
    return false;
  }
  // SIGKILL, then reaps it without reading on (a surviving grandchild may
  // still hold the pipe open).
  void Kill() {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    reaped_ = true;
  }
  // Reads the rest of the output and returns the exit status (-signal).
  int Wait() {
    WaitForLine("\x01never");
    int status = 0;
    ::waitpid(pid_, &status, 0);
    reaped_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  pid_t pid() const { return pid_; }
  const std::string& log() const { return log_; }

 private:
  pid_t pid_ = -1;
  FILE* out_ = nullptr;
  bool reaped_ = false;
  std::string log_;
};

class CrashSafetyTest : public TempDirTest {};

// Disk full: in a child whose files may not grow past 4 KB (RLIMIT_FSIZE,
// the same EFBIG a full disk gives as ENOSPC), each writer throws InputError
// naming the file and leaves the previous good file and no temporary.
TEST_F(CrashSafetyTest, FailingWriteKeepsTheLastGoodFile) {
  Checkpoint good;
  good.iteration = 7;
  good.gaussians = good.adam.m = good.adam.v = SomeGaussians(2);
  good.grad_sum = good.grad_count = good.max_radius = {0, 0};
  WriteCheckpoint(good, Path("checkpoint.bin"));
  WritePly(SomeGaussians(2), Path("static.ply"));
  MotionFieldOptions small;
  small.triplane.resolution = 2;
  small.triplane.channels = 1;
  small.mlp_width = 2;
  SaveMotionField(MotionField(small), Path("motion_field.bin"));
  WriteTextFileAtomically(Path("metrics.json"), "{}\n");
  const std::vector<std::string> files = {"checkpoint.bin", "static.ply",
                                          "motion_field.bin", "metrics.json"};
  std::vector<std::string> before;
  for (const std::string& f : files) before.push_back(ReadWholeFile(Path(f)));

  const pid_t pid = ::fork();
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit = {4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int failures = 0;
    auto expect_error = [&](const std::string& file, auto write) {
      try {
        write();
      } catch (const InputError& e) {
        if (std::string(e.what()).find(file) != std::string::npos) return;
      }
      ++failures;
    };
    Checkpoint big = good;
    big.iteration = 8;
    big.gaussians = big.adam.m = big.adam.v = SomeGaussians(500);
    big.grad_sum = big.grad_count = big.max_radius =
        std::vector<double>(500, 0);
    expect_error(Path("checkpoint.bin"),
                 [&] { WriteCheckpoint(big, Path("checkpoint.bin")); });
    expect_error(Path("static.ply"),
                 [&] { WritePly(SomeGaussians(500), Path("static.ply")); });
    MotionFieldOptions large = small;
    large.triplane.resolution = 32;
    expect_error(Path("motion_field.bin"), [&] {
      SaveMotionField(MotionField(large), Path("motion_field.bin"));
    });
    expect_error(Path("metrics.json"), [&] {
      WriteTextFileAtomically(Path("metrics.json"), std::string(10000, ' '));
    });
    ::_exit(failures);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "writers that did not report the error";
  for (size_t i = 0; i < files.size(); ++i)
    EXPECT_EQ(ReadWholeFile(Path(files[i])), before[i]) << files[i];
  EXPECT_EQ(ReadCheckpoint(Path("checkpoint.bin")).iteration, 7);
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_THAT(entry.path().string(), Not(HasSubstr(".tmp"))) << entry.path();
}

// A tiny synthetic scene shared by the process tests below.
class ProcessTest : public TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    for (const char* app : {"es_synth", "es_static", "eulersplat"})
      ASSERT_TRUE(fs::exists(kBin / app)) << app << ": build all targets";
    scene_ = Path("scene");
    Process synth({(kBin / "es_synth").string(), "--out", scene_, "--frames",
                   "8", "--width", "32", "--height", "24", "--detail",
                   "0.05", "--num_points", "100"});
    ASSERT_EQ(synth.Wait(), 0) << synth.log();
  }

  std::vector<std::string> StaticArgs(const std::string& out) const {
    return {(kBin / "es_static").string(), "--scene", scene_, "--out", out,
            "--iterations", std::to_string(kIterations), "--checkpoint_every",
            std::to_string(kInterval), "--log_every", "1", "--sh_degree", "1",
            "--sh_degree_interval", "30", "--densify_from", "20",
            "--densify_interval", "20", "--seed", "3"};
  }

  static constexpr int kIterations = 60;
  static constexpr int kInterval = 10;
  std::string scene_;
};

// kill -9 in the middle of Stage 1, then --resume: the rerun starts from
// the last checkpoint (at most one interval behind where the run was
// killed) and writes the same static.ply, bit for bit, as a run that was
// never interrupted.
TEST_F(ProcessTest, KilledStaticRunResumesAndEndsLikeACleanRun) {
  Process clean(StaticArgs(Path("clean")));
  ASSERT_EQ(clean.Wait(), 0) << clean.log();

  constexpr int kKillAfter = 25;
  Process killed(StaticArgs(Path("killed")));
  ASSERT_TRUE(killed.WaitForLine("iter " + std::to_string(kKillAfter) + "/"))
      << killed.log();
  killed.Kill();
  EXPECT_FALSE(fs::exists(Path("killed/static.ply")))
      << "the run ended before it was killed; raise kIterations";

  std::vector<std::string> args = StaticArgs(Path("killed"));
  args.push_back("--resume");
  Process resumed(args);
  ASSERT_EQ(resumed.Wait(), 0) << resumed.log();
  std::smatch m;
  const std::regex resumed_at("resumed from .* at iteration (\\d+)");
  ASSERT_TRUE(std::regex_search(resumed.log(), m, resumed_at))
      << resumed.log();
  const int from = std::stoi(m[1]);
  EXPECT_GE(from, kKillAfter / kInterval * kInterval);
  EXPECT_EQ(from % kInterval, 0);
  EXPECT_EQ(ReadWholeFile(Path("killed/static.ply")),
            ReadWholeFile(Path("clean/static.ply")));
  EXPECT_EQ(ReadWholeFile(Path("killed/checkpoint.bin")),
            ReadWholeFile(Path("clean/checkpoint.bin")));
}

// The parent pid of `pid` from /proc, or -1 once it is gone.
pid_t ParentOf(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return -1;
  // "pid (comm) state ppid ...": comm may hold spaces, so skip past ')'.
  std::istringstream rest(line.substr(line.rfind(')') + 2));
  char state;
  pid_t ppid;
  rest >> state >> ppid;
  return state == 'Z' ? -1 : ppid;  // a zombie has ended
}

std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> children;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    if (ParentOf(std::stoi(name)) == parent)
      children.push_back(std::stoi(name));
  }
  return children;
}

// D9: a second driver on the same --out is refused while the first runs,
// and kill -9 of the driver ends its stage too (no orphan trainer).
TEST_F(ProcessTest, DriverLocksItsOutputAndItsStageDiesWithIt) {
  const std::string out = Path("out");
  const std::vector<std::string> driver = {
      (kBin / "eulersplat").string(), "--scene", scene_, "--out", out,
      "--static_iterations", "100000", "--cycle_length", "4"};
  {
    const RunLock held(out, RunLock::Mode::kFailIfHeld);
    Process second(driver);
    EXPECT_EQ(second.Wait(), 1);
    EXPECT_THAT(second.log(), HasSubstr("another eulersplat run"));
  }

  Process first(driver);
  ASSERT_TRUE(first.WaitForLine("es_static")) << first.log();
  std::vector<pid_t> stage;
  for (int tries = 0; tries < 100 && stage.empty(); ++tries) {
    stage = ChildrenOf(first.pid());
    if (stage.empty())
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(stage.size(), 1u) << first.log();
  first.Kill();
  bool ended = false;
  for (int tries = 0; tries < 100 && !ended; ++tries) {
    ended = ParentOf(stage[0]) == -1;
    if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(ended) << "es_static (pid " << stage[0]
                     << ") outlived the killed driver";
  if (!ended) ::kill(stage[0], SIGKILL);
  // The lock died with the driver: a new one is granted at once.
  const RunLock again(out, RunLock::Mode::kFailIfHeld);
}

// Runs sharing a --static_dir take turns only until its Stages 1 and 2
// are written: a run in its joint stage no longer holds the folder.
TEST_F(ProcessTest, SharedStaticDirIsFreeDuringTheJointStage) {
  const std::string shared = Path("shared_static");
  const auto driver = [&](const std::string& out, const char* joint) {
    return std::vector<std::string>{
        (kBin / "eulersplat").string(), "--scene", scene_, "--out", out,
        "--static_dir", shared, "--preset", "quick", "--static_iterations",
        "30", "--flow_iterations", "10", "--joint_iterations", joint,
        "--cycle_length", "4", "--animate=false"};
  };
  Process first(driver(Path("first"), "5"));
  ASSERT_EQ(first.Wait(), 0) << first.log();

  Process second(driver(Path("second"), "100000"));
  ASSERT_TRUE(second.WaitForLine("es_train")) << second.log();
  EXPECT_NO_THROW(RunLock(shared, RunLock::Mode::kFailIfHeld))
      << "the joint stage still holds " << shared;
  second.Kill();
}

}  // namespace
}  // namespace es
