// Where a scene element was written, so every message can say `file:line:`.
#pragma once

#include <string>

namespace pvrt {

struct SourceLoc {
  std::string file;
  int line = 0;
  std::string str() const { return file + ":" + std::to_string(line); }
};

}  // namespace pvrt
