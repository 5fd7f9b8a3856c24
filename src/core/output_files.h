// Every file one run writes, checked before any work and committed together at the end.
//
// A run names its inputs and its outputs first; each output is checked at once (its folder
// exists and can be written, it is not an input, no two outputs are one file, it is not a
// directory), so that a bad path fails before minutes of rendering, not after. Each output
// is then written to a temporary file of its own (staged), created exclusively and without
// following links under an unpredictable name (`.NAME.pvrt-RANDOM.EXT`) in the folder of the
// file it will replace. commit() renames every staged file over its target; an error, an
// interrupt or an exception before that leaves every target as it was and no temporary behind.
//
// What a path names decides how it is written:
//   a regular file, or nothing yet  replaced atomically (rename), keeping its permissions;
//   a symbolic link                 its final target is replaced as above, the link kept;
//   a character device or a FIFO    written through (/dev/stdout, a pipe), at commit;
//   "-"                             standard output, written through at commit (pvrt's own
//                                   messages on standard output then go to standard error).
#pragma once

#include <memory>
#include <string>
#include <vector>

struct stat;

namespace pvrt {

class OutputFiles {
 public:
  OutputFiles();
  ~OutputFiles();  // removes whatever was staged and not committed
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // A file the run reads: no output may be it. Call before output().
  void input(const std::string& path);
  // Plans an output and checks it now; throws pvrt::Error(OutputError) `cannot write "PATH":
  // why`. `option` names it in messages (`-o`, `--save-scene`).
  void output(const std::string& path, const std::string& option);
  // A fresh temporary file for the planned output `path`, created empty, that the caller
  // (an image writer) fills by name. Its name keeps `path`'s extension (writers go by it);
  // for "-", `extension` names the format.
  std::string stage(const std::string& path, const std::string& extension = "");
  // Stages `bytes` as the whole of `path`; returns the temporary's name.
  std::string stageBytes(const std::string& path, const std::string& bytes);
  // Renames (or writes through) every staged output; throws pvrt::Error(OutputError).
  void commit();

 private:
  struct Planned;
  std::vector<std::unique_ptr<Planned>> planned_;
  std::vector<std::pair<unsigned long, unsigned long>> inputs_;  // (device, inode)
  Planned& find(const std::string& path);
};

// Creates an empty file `DIR/.STEM.pvrt-RANDOM.EXT` exclusively (O_EXCL | O_NOFOLLOW) and
// returns its name (and its stat, when `st` is given); errors name `forPath`.
std::string createTemporaryFile(const std::string& dir, const std::string& stem, const std::string& extension,
                                const std::string& forPath, struct stat* st = nullptr);

// Removes every staged, uncommitted temporary of the process: async-signal-safe, for a
// signal handler that is about to _exit().
void removeStagedFilesNow();

}  // namespace pvrt
