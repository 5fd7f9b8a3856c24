// Child processes for `pvrt golden`: renders, mpirun and POV-Ray run as separate programs
// (the real components, as a user runs them), several at once.
#pragma once

#include <string>
#include <vector>

namespace pvrt::golden {

struct Job {
  std::vector<std::string> argv;  // argv[0] is looked up in PATH
  std::string log;                // standard output and error go here (created or truncated)
  std::string cwd;                // empty: the current folder
};

struct JobResult {
  int exitCode = -1;  // 128 + signal when killed; 127 when the program could not be started
  double seconds = 0;
};

// Runs every job, at most `parallel` at once, and returns their results in the same order.
// When SIGINT or SIGTERM has been caught (interrupt::install), it starts no more, ends the
// running ones with that signal, waits for them and throws interrupt::error().
std::vector<JobResult> runJobs(const std::vector<Job>& jobs, int parallel);
JobResult runJob(const Job& job);

// The last `lines` lines of a log, for a failure message.
std::string tailOf(const std::string& log, int lines = 6);
// This program's own path (/proc/self/exe), to run `pvrt render` as a child.
std::string selfPath();
// The program's full path in PATH, or empty.
std::string findProgram(const std::string& name);

}  // namespace pvrt::golden
