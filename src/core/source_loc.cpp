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

}  // namespace pvrt
