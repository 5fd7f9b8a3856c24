#include "core/source_loc.h"

#include <mutex>
#include <unordered_set>

namespace pvrt {

namespace {

// Node-based, so the strings never move; never shrinks (a process reads few files).
struct Registry {
  std::mutex mutex;
  std::unordered_set<std::string> names;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: locations may outlive static destructors
  return *r;
}

}  // namespace

FileName::FileName(std::string_view name) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  name_ = &*r.names.emplace(name).first;
}

const std::string& FileName::str() const {
  static const std::string empty;
  return name_ ? *name_ : empty;
}

std::string printableName(std::string_view name) {
  std::string out;
  out.reserve(name.size());
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
      continue;
    }
    static const char hex[] = "0123456789abcdef";
    switch (c) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: out += std::string("\\x") + hex[u >> 4] + hex[u & 15];
    }
  }
  return out;
}

}  // namespace pvrt
