#include "image/oiio_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <filesystem>
#include <mutex>

#include "core/error.h"

namespace pvrt {

namespace {

constexpr const char* kModuleName = "libpvrt_oiio.so";

// Next to the running program first (an installed or copied build), then where CMake
// built it (tests run from other directories), then the loader's search path.
std::vector<std::string> candidates() {
  std::vector<std::string> paths;
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    exe[n] = '\0';
    const std::filesystem::path dir = std::filesystem::path(exe).parent_path();
    paths.push_back((dir / kModuleName).string());
    paths.push_back((dir / ".." / "lib" / kModuleName).string());
  }
#ifdef PVRT_OIIO_MODULE_PATH
  paths.push_back(PVRT_OIIO_MODULE_PATH);
#endif
  paths.push_back(kModuleName);
  return paths;
}

const OiioModule* load(std::string& why) {
  for (const std::string& path : candidates()) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      why = dlerror();
      continue;
    }
    using Entry = const OiioModule* (*)();
    if (auto entry = reinterpret_cast<Entry>(dlsym(handle, "pvrtOiioModule"))) return entry();
    why = path + " has no entry point";
  }
  return nullptr;
}

}  // namespace

const OiioModule& oiioModule() {
  static std::once_flag once;
  static const OiioModule* module = nullptr;
  static std::string why;
  std::call_once(once, [] { module = load(why); });
  if (!module) throw Error(ExitCode::OutputError, "cannot load the OpenImageIO module " + std::string(kModuleName) + ": " + why);
  return *module;
}

}  // namespace pvrt
