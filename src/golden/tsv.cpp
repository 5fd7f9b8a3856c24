#include "golden/tsv.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace pvrt::golden {

std::vector<std::string> readLines(const std::string& path, bool optional) {
  std::ifstream in(path);
  if (!in) {
    if (optional && errno == ENOENT) return {};
    throw Error(ExitCode::SceneError, printableName(path) + ": error: cannot read: " + std::strerror(errno));
  }
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  return lines;
}

std::vector<std::string> splitTabs(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (size_t tab; (tab = line.find('\t', start)) != std::string::npos; start = tab + 1)
    fields.push_back(line.substr(start, tab - start));
  fields.push_back(line.substr(start));
  return fields;
}

Error tsvError(const std::string& path, int line, const std::string& what) {
  return Error(ExitCode::SceneError, printableName(path) + ":" + std::to_string(line) + ": error: " + what);
}

int parseInt(const std::string& text, const std::string& path, int line, const std::string& column) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || v < 0 || v > 1000000)
    throw tsvError(path, line, column + " \"" + printableName(text) + "\" is not a whole number from 0 to 1000000");
  return int(v);
}

double parseDouble(const std::string& text, const std::string& path, int line, const std::string& column) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0 || v > 1)
    throw tsvError(path, line, column + " \"" + printableName(text) + "\" is not a number from 0 to 1");
  return v;
}

}  // namespace pvrt::golden
