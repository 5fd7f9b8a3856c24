#include "core/output_files.h"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/error.h"
#include "core/source_loc.h"

namespace fs = std::filesystem;

namespace pvrt {

namespace {

// The staged temporaries of the process, where a signal handler can reach them without
// allocating or locking: a slot is claimed, filled, then marked ready.
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled or emptied, 2 ready
  char path[4096];
};
std::array<Slot, 32> gSlots;

int registerStaged(const std::string& path) {
  if (path.size() >= sizeof(Slot::path)) return -1;
  for (size_t i = 0; i < gSlots.size(); ++i) {
    int free = 0;
    if (!gSlots[i].state.compare_exchange_strong(free, 1)) continue;
    std::memcpy(gSlots[i].path, path.c_str(), path.size() + 1);
    gSlots[i].state = 2;
    return int(i);
  }
  return -1;  // more than 32 at once: still removed by the destructor, not by a signal
}

void unregisterStaged(int slot) {
  if (slot >= 0) gSlots[size_t(slot)].state = 0;
}

std::string shown(const std::string& path) { return "\"" + printableName(path) + "\""; }

Error cannotWrite(const std::string& path, const std::string& why) {
  return Error(ExitCode::OutputError, "cannot write " + shown(path) + ": " + why);
}

std::string randomSuffix() {
  unsigned char bytes[8];
  if (getrandom(bytes, sizeof bytes, 0) != ssize_t(sizeof bytes)) {
    std::random_device rd;
    for (unsigned char& b : bytes) b = static_cast<unsigned char>(rd());
  }
  static const char hex[] = "0123456789abcdef";
  std::string s;
  for (unsigned char b : bytes) {
    s += hex[b >> 4];
    s += hex[b & 15];
  }
  return s;
}

// The file a chain of symbolic links ends at (which may not exist yet); `path` itself when
// it is not a link. Throws when the chain loops or is too long.
fs::path finalTarget(const std::string& path) {
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::error_code ec;
    const fs::path next = fs::read_symlink(p, ec);
    if (ec) throw cannotWrite(path, ec.message());
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  throw cannotWrite(path, "too many levels of symbolic links");
}

}  // namespace

struct OutputFiles::Planned {
  enum class Kind { File, Stream, Stdout } kind = Kind::File;
  std::string path, option;
  fs::path target;      // File: the file replaced (the final target of a link)
  std::string key;      // File: the target's folder, resolved, and its name: two equal keys are one file
  bool exists = false;  // the target exists (then dev, ino and mode are its)
  unsigned long dev = 0, ino = 0;
  mode_t mode = 0;
  std::string staged;  // the temporary, once staged
  unsigned long stagedDev = 0, stagedIno = 0;
  int slot = -1;
  int fd = -1;  // Stdout: standard output as it was when planned
  bool committed = false;

  ~Planned() {
    if (!staged.empty() && !committed) ::unlink(staged.c_str());
    unregisterStaged(slot);
    if (fd >= 0) ::close(fd);
  }
};

namespace {

std::string createTemporary(const std::string& dir, const std::string& stem, const std::string& extension,
                            const std::string& forPath, struct stat* st, int* slot) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path tmp = fs::path(dir) / ("." + stem + ".pvrt-" + randomSuffix() + extension);
    // Known to the signal handlers before it exists, so that no signal can leave it behind.
    if (slot) *slot = registerStaged(tmp.string());
    // Exclusive and no-follow: a file or link already at the name is never opened.
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    const int err = errno;
    if (fd < 0 && slot) {
      unregisterStaged(*slot);
      *slot = -1;
    }
    if (fd < 0 && err == EEXIST) continue;
    if (fd < 0) throw cannotWrite(forPath, std::strerror(err));
    if (st) ::fstat(fd, st);
    ::close(fd);
    return tmp.string();
  }
  throw cannotWrite(forPath, "no free temporary name");
}

}  // namespace

std::string createTemporaryFile(const std::string& dir, const std::string& stem, const std::string& extension,
                                const std::string& forPath, struct stat* st) {
  return createTemporary(dir, stem, extension, forPath, st, nullptr);
}

OutputFiles::OutputFiles() = default;
OutputFiles::~OutputFiles() = default;

void OutputFiles::input(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) inputs_.emplace_back(st.st_dev, st.st_ino);
}

void OutputFiles::output(const std::string& path, const std::string& option) {
  auto p = std::make_unique<Planned>();
  p->path = path;
  p->option = option;
  if (path.empty()) throw Error(ExitCode::Usage, option + " needs a file name");
  if (path == "-") {
    for (const auto& other : planned_)
      if (other->kind == Planned::Kind::Stdout)
        throw cannotWrite(path, "standard output is already the output of " + other->option);
    // pvrt's own messages must not mix with the file: standard output is kept for the file,
    // and what pvrt prints there goes to standard error from now on.
    std::fflush(stdout);
    p->kind = Planned::Kind::Stdout;
    p->fd = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (p->fd < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) throw cannotWrite(path, std::strerror(errno));
    planned_.push_back(std::move(p));
    return;
  }
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) throw cannotWrite(path, "it is a directory");
  // Devices, pipes and whatever /dev or /proc name (/dev/stdout, /proc/self/fd/1) are
  // written through: replacing them with a regular file is never what was meant.
  const bool special = path.rfind("/dev/", 0) == 0 || path.rfind("/proc/", 0) == 0;
  if (exists && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode) || (special && S_ISREG(st.st_mode)))) {
    p->kind = Planned::Kind::Stream;
    if (::access(path.c_str(), W_OK) != 0) throw cannotWrite(path, std::strerror(errno));
  } else if (exists && !S_ISREG(st.st_mode)) {
    throw cannotWrite(path, "not a regular file, a character device or a FIFO");
  } else {
    p->target = finalTarget(path);
    const fs::path dir = p->target.parent_path().empty() ? fs::path(".") : p->target.parent_path();
    struct stat ds {};
    if (::stat(dir.c_str(), &ds) != 0) {
      if (errno == ENOENT) throw cannotWrite(path, "no such directory " + shown(dir.string()));
      throw cannotWrite(path, std::strerror(errno));
    }
    if (!S_ISDIR(ds.st_mode)) throw cannotWrite(path, shown(dir.string()) + " is not a directory");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw cannotWrite(path, "the directory " + shown(dir.string()) + " is not writable (" + std::strerror(errno) + ")");
    std::error_code ec;
    p->key = fs::canonical(dir, ec).string() + "/" + p->target.filename().string();
    if (ec) p->key = fs::absolute(p->target).lexically_normal().string();
  }
  if (exists) {
    p->exists = true;
    p->dev = st.st_dev;
    p->ino = st.st_ino;
    p->mode = st.st_mode;
    for (const auto& [dev, ino] : inputs_)
      if (dev == st.st_dev && ino == st.st_ino) throw cannotWrite(path, "it is an input of this run");
  }
  for (const auto& other : planned_) {
    const bool same = (p->exists && other->exists && p->dev == other->dev && p->ino == other->ino) ||
                      (!p->key.empty() && p->key == other->key);
    if (same) throw cannotWrite(path, "it is also the output of " + other->option + " (" + shown(other->path) + ")");
  }
  planned_.push_back(std::move(p));
}

OutputFiles::Planned& OutputFiles::find(const std::string& path) {
  for (auto& p : planned_)
    if (p->path == path) return *p;
  throw Error(ExitCode::Internal, "pvrt: internal error: output " + shown(path) + " was not planned");
}

std::string OutputFiles::stage(const std::string& path, const std::string& extension) {
  Planned& p = find(path);
  if (!p.staged.empty()) {  // staged again: the earlier temporary is dropped
    ::unlink(p.staged.c_str());
    unregisterStaged(p.slot);
    p.staged.clear();
    p.slot = -1;
  }
  // Files are staged beside the file they replace (a rename never crosses file systems);
  // streams in the temporary directory, copied through at commit.
  fs::path dir, name;
  std::string ext;
  if (p.kind == Planned::Kind::File) {
    dir = p.target.parent_path();
    name = p.target.filename();
    ext = p.target.extension().string();
  } else {
    std::error_code ec;
    dir = fs::temp_directory_path(ec);
    if (ec) dir = "/tmp";
    name = "pvrt-output";
    ext = p.kind == Planned::Kind::Stdout ? extension : fs::path(path).extension().string();
  }
  struct stat st {};
  p.staged = createTemporary(dir.string(), fs::path(name).stem().string(), ext, path, &st, &p.slot);
  p.stagedDev = st.st_dev;
  p.stagedIno = st.st_ino;
  if (p.kind == Planned::Kind::File && p.exists) ::chmod(p.staged.c_str(), p.mode & 07777);  // keep its permissions
  return p.staged;
}

std::string OutputFiles::stageBytes(const std::string& path, const std::string& bytes) {
  const std::string tmp = stage(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_TRUNC | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) throw cannotWrite(path, std::strerror(errno));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      ::close(fd);
      throw cannotWrite(path, std::strerror(err));
    }
    done += size_t(n);
  }
  if (::close(fd) != 0) throw cannotWrite(path, std::strerror(errno));
  return tmp;
}

namespace {

// Copies the file `from` to the descriptor `to`. Empty on success, else why not.
std::string copyThrough(const std::string& from, int to) {
  const int in = ::open(from.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (in < 0) return std::strerror(errno);
  // A reader that went away is an error to report (EPIPE), not a signal that ends pvrt.
  struct sigaction ignore {}, old {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  ::sigaction(SIGPIPE, &ignore, &old);
  std::string why;
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(in, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) why = std::strerror(errno);
    if (n <= 0) break;
    for (ssize_t done = 0; done < n && why.empty();) {
      const ssize_t w = ::write(to, buf + done, size_t(n - done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) why = std::strerror(w < 0 ? errno : EIO);
      else done += w;
    }
    if (!why.empty()) break;
  }
  ::sigaction(SIGPIPE, &old, nullptr);
  ::close(in);
  return why;
}

}  // namespace

void OutputFiles::commit() {
  // Every output must have been written in full before any is committed.
  for (const auto& p : planned_) {
    if (p->staged.empty()) throw Error(ExitCode::Internal, "pvrt: internal error: " + shown(p->path) + " not staged");
    struct stat st {};
    if (::lstat(p->staged.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_dev != p->stagedDev ||
        st.st_ino != p->stagedIno)
      throw cannotWrite(p->path, "its temporary file " + shown(p->staged) + " was replaced or removed");
  }
  // The streams first, then the renames. A stream is what fails in practice (a reader gone, a
  // full device), and then no file the user had has been replaced yet; a rename fails only
  // when its folder changed under the run, and what a stream's reader got was whole anyway.
  for (const auto& p : planned_) {
    if (p->kind == Planned::Kind::File) continue;
    std::string why;
    if (p->kind == Planned::Kind::Stdout) {
      why = copyThrough(p->staged, p->fd);
    } else {
      const int fd = ::open(p->path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
      why = fd < 0 ? std::strerror(errno) : copyThrough(p->staged, fd);
      if (fd >= 0 && ::close(fd) != 0 && why.empty()) why = std::strerror(errno);
    }
    ::unlink(p->staged.c_str());
    p->committed = true;
    if (!why.empty()) throw cannotWrite(p->path, why);
  }
  for (const auto& p : planned_) {
    if (p->kind != Planned::Kind::File) continue;
    if (std::rename(p->staged.c_str(), p->target.c_str()) != 0) throw cannotWrite(p->path, std::strerror(errno));
    p->committed = true;
    unregisterStaged(p->slot);
    p->slot = -1;
  }
}

void removeStagedFilesNow() {
  for (Slot& s : gSlots)
    if (s.state.load() == 2) ::unlink(s.path);
}

}  // namespace pvrt
