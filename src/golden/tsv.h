// The tab-separated files of a golden suite: lines split at tabs, numbers read strictly, and
// errors that name the file and line.
#pragma once

#include <string>
#include <vector>

#include "core/error.h"

namespace pvrt::golden {

// The file's lines (without their newline); an absent file gives none when `optional`,
// else throws pvrt::Error(SceneError) `FILE: error: cannot read: why`.
std::vector<std::string> readLines(const std::string& path, bool optional);
std::vector<std::string> splitTabs(const std::string& line);

// `FILE:LINE: error: what`, exit code 3 like any bad input.
Error tsvError(const std::string& path, int line, const std::string& what);
int parseInt(const std::string& text, const std::string& path, int line, const std::string& column);
double parseDouble(const std::string& text, const std::string& path, int line, const std::string& column);

}  // namespace pvrt::golden
