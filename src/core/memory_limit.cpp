#include "core/memory_limit.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/decimal_text.h"
#include "core/error.h"

namespace pvrt {

namespace {
// The number in the first line of `path`, or 0 ("max", missing, unreadable).
size_t readLimit(const char* path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word.empty() || !std::isdigit(static_cast<unsigned char>(word[0]))) return 0;
  return size_t(std::strtoull(word.c_str(), nullptr, 10));
}
}  // namespace

size_t availableMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  size_t bytes = pages > 0 && page > 0 ? size_t(pages) * size_t(page) : size_t(4) << 30;
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const size_t limit = readLimit(path);
    if (limit > 0) bytes = std::min(bytes, limit);
  }
  return bytes;
}

size_t defaultMemoryLimit() { return availableMemory() / 4; }

size_t parseMemorySize(const std::string& text) {
  const auto bad = [&] {
    return Error(ExitCode::Usage,
                 "pvrt: error: --memory-limit: expected a size such as 2G, 512M or 100000K (bytes "
                 "without a suffix), got \"" +
                     text + "\"");
  };
  // The number in decimal digits, as every number pvrt reads (stod took "0x100M" as 256M).
  const bool suffixed = !text.empty() && std::isalpha(static_cast<unsigned char>(text.back()));
  const size_t used = suffixed ? text.size() - 1 : text.size();
  const std::string number = text.substr(0, used);
  if (!isDecimalNumber(number)) throw bad();
  double value = 0;
  std::from_chars(number.data(), number.data() + number.size(), value);
  std::string suffix = text.substr(used);
  double scale = 1;
  if (suffix.size() == 1) {
    switch (std::toupper(static_cast<unsigned char>(suffix[0]))) {
      case 'K': scale = 0x1p10; break;
      case 'M': scale = 0x1p20; break;
      case 'G': scale = 0x1p30; break;
      case 'T': scale = 0x1p40; break;
      default: throw bad();
    }
  } else if (!suffix.empty()) {
    throw bad();
  }
  const double bytes = value * scale;
  if (!(bytes >= 1) || !(bytes < 0x1p62) || !std::isdigit(static_cast<unsigned char>(text[0])))
    throw bad();
  return size_t(bytes);
}

std::string formatBytes(size_t bytes) {
  char buf[32];
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1024 && u < 4) v /= 1024, ++u;
  if (u == 0) std::snprintf(buf, sizeof buf, "%zu bytes", bytes);
  else std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
  return buf;
}

}  // namespace pvrt
