#include "scene/xml_split.h"

#include <algorithm>
#include <cstring>

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
  // skipped with one memchr for its closing quote.
  bool startTag(bool& empty) {
    for (size_t i = pos + 1; i < s_.size(); ++i) {
      const char c = s_[i];
      if (c == '"' || c == '\'') {
        const void* close = std::memchr(s_.data() + i + 1, c, s_.size() - i - 1);
        if (!close) return false;
        i = size_t(static_cast<const char*>(close) - s_.data());
      } else if (c == '>') {
        empty = s_[i - 1] == '/';
        pos = i + 1;
        return true;
      } else if (c == '<') {
        return false;
      }
    }
    return false;
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
      if (at("<!--")) {
        if (!skipPast("-->")) return false;
      } else if (at("<![CDATA[")) {
        if (!skipPast("]]>")) return false;
      } else if (at("</")) {
        const size_t close = s_.find('>', pos);
        if (close == std::string_view::npos || s_.find('<', pos + 1) < close) return false;
        pos = close + 1;
        if (--depth == 0) return true;
      } else if (at("<!") || at("<?")) {
        return false;
      } else {
        bool empty = false;
        if (!startTag(empty)) return false;
        if (!empty && ++depth > kMaxDepth) return false;
        if (empty && depth == 0) return true;
      }
      pos = s_.find('<', pos);  // the text up to the next tag is the element's business
      if (pos == std::string_view::npos) return false;
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
  XmlPiece piece{scan.pos, scan.pos, 1 + newlines(bytes, 0, scan.pos)};
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
      piece = {scan.pos, scan.pos, piece.firstLine + newlines(bytes, piece.begin, scan.pos), 0};
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
  return split;
}

}  // namespace pvrt
