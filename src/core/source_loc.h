// Where a scene element was written, so every message can say `file:line:`.
#pragma once

#include <string>
#include <string_view>

namespace pvrt {

// A file name kept once for the life of the process (interned), so that a location is two
// words, copied without allocating: a big scene keeps several locations per object, and a
// path longer than a std::string's inline buffer would cost each of them a heap copy.
class FileName {
 public:
  FileName() = default;
  FileName(std::string_view name);  // NOLINT(google-explicit-constructor): a name is a FileName
  FileName(const std::string& name) : FileName(std::string_view(name)) {}  // NOLINT
  FileName(const char* name) : FileName(std::string_view(name)) {}         // NOLINT

  const std::string& str() const;
  bool operator==(const FileName&) const = default;  // names are interned: one pointer each

 private:
  const std::string* name_ = nullptr;
};

// `name` as messages show it: control characters (a newline in a file name, say) escaped as
// \n, \r, \t or \xNN, so that every message stays one line.
std::string printableName(std::string_view name);

struct SourceLoc {
  FileName file;
  int line = 0;
  std::string str() const { return printableName(file.str()) + ":" + std::to_string(line); }
  bool operator==(const SourceLoc&) const = default;
};

}  // namespace pvrt
