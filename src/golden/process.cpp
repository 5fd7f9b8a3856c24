#include "golden/process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/interrupt.h"

extern char** environ;

namespace pvrt::golden {

namespace {

using Clock = std::chrono::steady_clock;

pid_t start(const Job& job) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, job.log.empty() ? "/dev/null" : job.log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  if (!job.cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, job.cwd.c_str());
  std::vector<char*> argv;
  for (const std::string& a : job.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

int exitCodeOf(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

// Ctrl-C at a terminal reaches the renders too, but a signal sent to pvrt alone must not
// leave them running: each gets the signal pvrt caught, and each is waited for before the
// interrupt ends the run (so nothing is still writing once pvrt has exited).
template <typename Running>
void endAll(const Running& running) {
  for (const auto& [pid, job] : running) kill(pid, interrupt::caught().load());
  for (const auto& [pid, job] : running)
    while (waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
}

}  // namespace

std::vector<JobResult> runJobs(const std::vector<Job>& jobs, int parallel) {
  std::vector<JobResult> results(jobs.size());
  std::map<pid_t, std::pair<size_t, Clock::time_point>> running;
  size_t next = 0;
  while (next < jobs.size() || !running.empty()) {
    if (interrupt::requested()) {  // start nothing more; the callers' scratch goes as the error unwinds
      endAll(running);
      interrupt::check();
    }
    while (next < jobs.size() && int(running.size()) < std::max(1, parallel)) {
      const pid_t pid = start(jobs[next]);
      if (pid < 0) results[next].exitCode = 127;
      else running[pid] = {next, Clock::now()};
      ++next;
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0 && errno == EINTR) continue;  // a signal: the loop's head decides
    if (pid < 0) break;
    auto it = running.find(pid);
    if (it == running.end()) continue;
    JobResult& r = results[it->second.first];
    r.exitCode = exitCodeOf(status);
    r.seconds = std::chrono::duration<double>(Clock::now() - it->second.second).count();
    running.erase(it);
  }
  return results;
}

JobResult runJob(const Job& job) { return runJobs({job}, 1).front(); }

std::string tailOf(const std::string& log, int lines) {
  std::ifstream in(log);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);) all.push_back(line);
  std::string s;
  for (size_t i = all.size() > size_t(lines) ? all.size() - size_t(lines) : 0; i < all.size(); ++i)
    s += all[i] + "\n";
  return s;
}

std::string selfPath() {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? "pvrt" : p.string();
}

std::string findProgram(const std::string& name) {
  if (name.find('/') != std::string::npos) return access(name.c_str(), X_OK) == 0 ? name : "";
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::string full = (dir.empty() ? "." : dir) + "/" + name;
    if (access(full.c_str(), X_OK) == 0) return full;
  }
  return "";
}

}  // namespace pvrt::golden
