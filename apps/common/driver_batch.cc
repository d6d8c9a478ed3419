#include "apps/common/driver_batch.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "core/base/input_error.h"
#include "core/io/output_dir.h"

namespace es {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string Trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

// Starts `path args` with stdout and stderr into `log`; its pid.
pid_t StartLogged(const std::string& path, std::vector<std::string> args,
                  const std::string& log) {
  args.insert(args.begin(), path);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0)
    throw InputError(log + ": cannot write (" + std::strerror(errno) + ")");
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    throw InputError(path + ": cannot start (" + std::strerror(errno) + ")");
  }
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec; the scene's run
    // ends with the batch.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::execv(path.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fd);
  return pid;
}

// A scene's run in progress: its log read as it grows.
struct SceneRun {
  size_t scene = 0;
  size_t group = 0;
  pid_t pid = 0;
  std::string log;
  std::streamoff read = 0;  // bytes of the log already looked at
  std::string tail;         // its last lines, for a failure's report
  Clock::time_point start;
};

// Prints the log's new whole lines that mark the run's progress, prefixed
// with the scene's name; keeps the last few lines of any kind.
void ForwardProgress(const std::string& name, SceneRun* run) {
  std::ifstream in(run->log, std::ios::binary);
  in.seekg(run->read);
  std::string line;
  while (std::getline(in, line) && !in.eof()) {
    run->read += static_cast<std::streamoff>(line.size()) + 1;
    if (line.rfind("[eulersplat] ", 0) == 0)
      std::printf("[%s] %s\n", name.c_str(), line.c_str() + 13);
    if (!Trim(line).empty()) {
      run->tail += line + "\n";
      size_t lines = std::count(run->tail.begin(), run->tail.end(), '\n');
      for (; lines > 3; --lines) run->tail.erase(0, run->tail.find('\n') + 1);
    }
  }
  std::fflush(stdout);
}

}  // namespace

std::vector<std::string> ParseSceneList(const std::string& value) {
  std::vector<std::string> scenes;
  std::string item;
  if (fs::is_regular_file(value)) {
    std::ifstream in(value);
    while (std::getline(in, item)) {
      item = Trim(item.substr(0, item.find('#')));
      if (!item.empty()) scenes.push_back(item);
    }
    return scenes;
  }
  std::stringstream list(value);
  while (std::getline(list, item, ',')) {
    item = Trim(item);
    if (!item.empty()) scenes.push_back(item);
  }
  return scenes;
}

std::vector<int> GroupRanks(int ranks, int groups) {
  std::vector<int> sizes(groups, ranks / groups);
  for (int g = 0; g < ranks % groups; ++g) ++sizes[g];
  return sizes;
}

std::string SceneName(const std::string& dir) {
  fs::path path = fs::path(dir).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();
  return path.filename().string();
}

SceneBatchOptions CheckSceneBatch(SceneBatchOptions o) {
  if (o.scenes.empty())
    throw InputError("--scenes: no scene directory given");
  std::set<std::string> names;
  for (const std::string& dir : o.scenes) {
    if (!fs::is_directory(dir)) {
      throw InputError("--scenes: '" + dir +
                       "' is not a scene directory (or a file listing "
                       "them, one per line)");
    }
    const std::string name = SceneName(dir);
    if (name.empty() || name == "." || name == ".." ||
        !names.insert(name).second) {
      throw InputError("--scenes: two scenes would write to " + o.out + "/" +
                       name + "; give each scene a folder of its own name");
    }
  }
  if (o.ranks < 1)
    throw InputError("--ranks must be >= 1, got " + std::to_string(o.ranks));
  if (o.groups == 0)
    o.groups = std::min(o.ranks, static_cast<int>(o.scenes.size()));
  if (o.groups < 1 || o.groups > o.ranks) {
    throw InputError("--groups " + std::to_string(o.groups) +
                     ": each group of ranks runs one scene at a time, so it "
                     "must be between 1 and --ranks (" +
                     std::to_string(o.ranks) + ")");
  }
  return o;
}

int RunSceneBatch(const SceneBatchOptions& o) {
  PrepareOutputDirectory(o.out, "out");
  const std::vector<int> group_ranks = GroupRanks(o.ranks, o.groups);
  std::printf("[batch] %zu scene(s) on %d rank(s) in %d group(s) of %d%s "
              "rank(s); each scene's output in %s/<name>, its log in "
              "%s/<name>.log\n",
              o.scenes.size(), o.ranks, o.groups, group_ranks.back(),
              group_ranks.front() != group_ranks.back()
                  ? ("-" + std::to_string(group_ranks.front())).c_str()
                  : "",
              o.out.c_str(), o.out.c_str());
  std::deque<size_t> waiting;
  for (size_t s = 0; s < o.scenes.size(); ++s) waiting.push_back(s);
  std::deque<size_t> free_groups;
  for (int g = 0; g < o.groups; ++g) free_groups.push_back(g);
  std::vector<SceneRun> running;
  std::vector<std::string> failed;
  while (!waiting.empty() || !running.empty()) {
    while (!waiting.empty() && !free_groups.empty()) {
      SceneRun run;
      run.scene = waiting.front();
      run.group = free_groups.front();
      waiting.pop_front();
      free_groups.pop_front();
      const std::string name = SceneName(o.scenes[run.scene]);
      const int ranks = group_ranks[run.group];
      // The batch's threads shared in proportion to the group's ranks.
      const int threads = std::max(1, o.threads / o.ranks);
      std::vector<std::string> args = {
          "--scene", o.scenes[run.scene], "--out", o.out + "/" + name,
          "--ranks", std::to_string(ranks), "--threads",
          std::to_string(threads)};
      args.insert(args.end(), o.flags.begin(), o.flags.end());
      run.log = o.out + "/" + name + ".log";
      run.start = Clock::now();
      run.pid = StartLogged(o.self, args, run.log);
      std::printf("[batch] %s: started on %d rank(s) (group %zu)\n",
                  name.c_str(), ranks, run.group + 1);
      std::fflush(stdout);
      running.push_back(std::move(run));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    for (size_t r = 0; r < running.size();) {
      SceneRun& run = running[r];
      const std::string name = SceneName(o.scenes[run.scene]);
      ForwardProgress(name, &run);
      int status = 0;
      const pid_t done = ::waitpid(run.pid, &status, WNOHANG);
      if (done == 0 || (done < 0 && errno == EINTR)) {
        ++r;
        continue;
      }
      ForwardProgress(name, &run);
      const double seconds =
          std::chrono::duration<double>(Clock::now() - run.start).count();
      const int code = done < 0             ? 128
                       : WIFEXITED(status)  ? WEXITSTATUS(status)
                       : WIFSIGNALED(status) ? 128 + WTERMSIG(status)
                                             : 128;
      if (code == 0) {
        std::printf("[batch] %s: done in %.0f s\n", name.c_str(), seconds);
      } else {
        failed.push_back(name);
        std::printf("[batch] %s: FAILED (exit status %d) after %.0f s; the "
                    "end of %s:\n%s",
                    name.c_str(), code, seconds, run.log.c_str(),
                    run.tail.c_str());
      }
      std::fflush(stdout);
      free_groups.push_back(run.group);
      running.erase(running.begin() + r);
    }
  }
  std::printf("[batch] %zu of %zu scene(s) done",
              o.scenes.size() - failed.size(), o.scenes.size());
  for (size_t f = 0; f < failed.size(); ++f)
    std::printf("%s%s", f == 0 ? "; failed: " : ", ", failed[f].c_str());
  std::printf("\n");
  return static_cast<int>(failed.size());
}

}  // namespace es
