#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace pvrt {

std::string temporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path p(path);
  const std::string name = "." + p.stem().string() + ".tmp-" + std::to_string(getpid()) + "-" +
                           std::to_string(counter++) + p.extension().string();
  return (p.parent_path() / name).string();
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
  const std::string tmp = temporarySibling(path);
  auto fail = [&](const std::string& why) {
    std::remove(tmp.c_str());
    return Error(ExitCode::OutputError, "cannot write \"" + path + "\": " + why);
  };
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw fail(std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) throw fail(std::strerror(ok ? errno : err));
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw fail(ec.message());
}

}  // namespace pvrt
