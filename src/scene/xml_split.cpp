#include "scene/xml_split.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include "parallel/parallel_for.h"

namespace pvrt {

namespace {

// Deeper nesting than any scene has; past it the scan gives up (and tinyxml2's own depth
// limit is left to the whole-file parse to report).
constexpr int kMaxDepth = 64;

class Scanner {
 public:
  explicit Scanner(std::string_view s) : s_(s) {}

  size_t pos = 0;
  size_t lastElementEnd = 0;

  bool at(std::string_view prefix) const { return s_.compare(pos, prefix.size(), prefix) == 0; }
  bool done() const { return pos >= s_.size(); }
  bool skipPast(std::string_view end) {
    const size_t found = s_.find(end, pos);
    if (found == std::string_view::npos) return false;
    pos = found + end.size();
    return true;
  }
  void skipSpace() {
    while (pos < s_.size() && (s_[pos] == ' ' || s_[pos] == '\t' || s_[pos] == '\r' || s_[pos] == '\n')) ++pos;
  }
  // At the '<' of a start tag: moves past its '>' (quoted attribute values may hold one);
  // `empty` tells a self-closing tag. Most of a scene's bytes are attribute values: each is
  // skipped with one memchr for its closing quote, and the rest eight bytes at a time.
  bool startTag(bool& empty) {
    for (size_t i = nextMarkup(pos + 1); i < s_.size(); i = nextMarkup(i + 1)) {
      const char c = s_[i];
      if (c == '"' || c == '\'') {
        const void* close = std::memchr(s_.data() + i + 1, c, s_.size() - i - 1);
        if (!close) return false;
        i = size_t(static_cast<const char*>(close) - s_.data());
      } else if (c == '>') {
        empty = s_[i - 1] == '/';
        pos = i + 1;
        return true;
      } else {  // '<'
        return false;
      }
    }
    return false;
  }
  // The first '"', '\'', '<' or '>' at or after `i`, else s_.size().
  size_t nextMarkup(size_t i) const {
    auto markup = [](char c) { return c == '"' || c == '\'' || c == '<' || c == '>'; };
    if constexpr (std::endian::native == std::endian::little) {
      // A byte of `w` equal to c is a zero byte of w ^ (c in every byte); the lowest flag
      // of zeroBytes() is exact (those above it may not be), and it is the first in memory.
      constexpr uint64_t kOnes = 0x0101010101010101ull, kHigh = 0x8080808080808080ull;
      auto zeroBytes = [](uint64_t v) { return (v - kOnes) & ~v & kHigh; };
      for (; i + 8 <= s_.size(); i += 8) {
        uint64_t w;
        std::memcpy(&w, s_.data() + i, 8);
        const uint64_t hit = zeroBytes(w ^ (kOnes * '"')) | zeroBytes(w ^ (kOnes * '\'')) |
                             zeroBytes(w ^ (kOnes * '<')) | zeroBytes(w ^ (kOnes * '>'));
        if (hit) return i + size_t(std::countr_zero(hit) >> 3);
      }
    }
    while (i < s_.size() && !markup(s_[i])) ++i;
    return i;
  }
  // At the '<' of a start tag: the tag's name, as far as the scan can tell.
  std::string_view name() const {
    size_t end = pos + 1;
    while (end < s_.size() && std::strchr(" \t\r\n/>", s_[end]) == nullptr) ++end;
    return s_.substr(pos + 1, end - pos - 1);
  }
  // At the '<' of an element's start tag: moves past the end of the element.
  bool element() {
    for (int depth = 0;;) {
      const char next = pos + 1 < s_.size() ? s_[pos + 1] : '\0';
      if (next == '/') {  // an end tag: no '<' before its '>'
        size_t i = pos + 2;
        while (i < s_.size() && s_[i] != '>' && s_[i] != '<') ++i;
        if (i == s_.size() || s_[i] == '<') return false;
        pos = i + 1;
        if (--depth == 0) return true;
      } else if (next == '!') {
        if (at("<!--")) {
          if (!skipPast("-->")) return false;
        } else if (at("<![CDATA[")) {
          if (!skipPast("]]>")) return false;
        } else {
          return false;
        }
      } else if (next == '?') {
        return false;
      } else {
        bool empty = false;
        if (!startTag(empty)) return false;
        if (!empty && ++depth > kMaxDepth) return false;
        if (empty && depth == 0) return true;
      }
      // The text up to the next tag (a few spaces, as a rule) is the element's business.
      while (pos < s_.size() && s_[pos] != '<') ++pos;
      if (pos == s_.size()) return false;
    }
  }

 private:
  std::string_view s_;
};

int newlines(std::string_view s, size_t from, size_t to) {
  return int(std::count(s.begin() + std::ptrdiff_t(from), s.begin() + std::ptrdiff_t(to), '\n'));
}

}  // namespace

std::optional<XmlSplit> splitXmlRoot(std::string_view bytes, size_t pieceBytes,
                                     const std::function<bool(std::string_view name)>& counts) {
  Scanner scan(bytes);
  if (scan.at("\xEF\xBB\xBF")) scan.pos += 3;  // a UTF-8 byte order mark
  for (;;) {                                  // the prolog: declaration and comments
    scan.skipSpace();
    if (scan.at("<?")) {
      if (!scan.skipPast("?>")) return std::nullopt;
    } else if (scan.at("<!--")) {
      if (!scan.skipPast("-->")) return std::nullopt;
    } else if (scan.at("<") && !scan.at("<!")) {
      break;
    } else {
      return std::nullopt;
    }
  }
  bool empty = false;
  if (!scan.startTag(empty) || empty) return std::nullopt;

  XmlSplit split;
  split.bodyBegin = scan.pos;
  XmlPiece piece{scan.pos, scan.pos};
  for (;;) {
    scan.skipSpace();
    if (scan.done()) return std::nullopt;
    if (scan.at("<!--")) {
      if (!scan.skipPast("-->")) return std::nullopt;
      continue;
    }
    if (scan.at("</")) break;  // the root's end tag
    if (!scan.at("<") || scan.at("<!") || scan.at("<?")) return std::nullopt;
    if (counts && counts(scan.name())) ++piece.counted;
    if (!scan.element()) return std::nullopt;
    ++split.elements;
    scan.lastElementEnd = scan.pos;
    if (scan.pos - piece.begin >= pieceBytes) {
      piece.end = scan.pos;
      split.pieces.push_back(piece);
      piece = {scan.pos, scan.pos};
    }
  }
  split.bodyEnd = scan.pos;
  // What follows the last cut joins the last piece when it holds no element: tinyxml2
  // refuses a document of nothing but space.
  if (piece.begin == scan.lastElementEnd && !split.pieces.empty()) {
    split.pieces.back().end = split.bodyEnd;
  } else {
    piece.end = split.bodyEnd;
    split.pieces.push_back(piece);
  }
  // Lines, counted by every thread a piece each: a pass over the whole file.
  std::vector<int> lines(split.pieces.size());
  parallelIndices(lines.size(), 0, [&](size_t k) { lines[k] = newlines(bytes, split.pieces[k].begin, split.pieces[k].end); });
  int line = 1 + newlines(bytes, 0, split.bodyBegin);
  for (size_t k = 0; k < lines.size(); ++k) {
    split.pieces[k].firstLine = line;
    line += lines[k];
    split.bodyLines += lines[k];
  }
  return split;
}

}  // namespace pvrt
