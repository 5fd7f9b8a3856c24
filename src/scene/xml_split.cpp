#include "scene/xml_split.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/interrupt.h"
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

// The line feeds in s[from, to): 32 bytes at a time where AVX2 is there (a big scene's
// pieces hold hundreds of megabytes between them).
int newlines(std::string_view s, size_t from, size_t to) {
  size_t n = 0;
#if defined(__AVX2__)
  const __m256i lf = _mm256_set1_epi8('\n');
  for (; from + 32 <= to; from += 32) {
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.data() + from));
    n += size_t(std::popcount(uint32_t(_mm256_movemask_epi8(_mm256_cmpeq_epi8(v, lf)))));
  }
#endif
  return int(n + size_t(std::count(s.begin() + std::ptrdiff_t(from), s.begin() + std::ptrdiff_t(to), '\n')));
}

// What the scan of the root's children meets, in order: a child ending (at `pos`, counted or
// not), an end tag where a child could begin (the root's, at `pos`), or something that makes
// it give up; and, where a part of the body is scanned from a guessed place, the place just
// after such an end tag, where the scan goes on.
struct Met {
  enum Kind : uint8_t { Child, CountedChild, EndTag, GiveUp, Resumed };
  Met(size_t pos, Kind kind) : bits_(uint64_t(pos) << 3 | kind) {}
  size_t pos() const { return size_t(bits_ >> 3); }
  Kind kind() const { return Kind(bits_ & 7); }

 private:
  uint64_t bits_;  // a child of every hundred bytes or so: a million of them for 10^6 spheres
};

// Scans the root's children from `pos`, which lies between two of them, until a child ends at
// or past `stop`, an end tag or a give-up; appends what it met to `out`. With `resume`, an
// end tag does not end the scan: a part of the body scanned from a guessed place may have
// begun inside a child, whose end tag this is, and the root's next child may follow.
void scanChildren(std::string_view bytes, size_t pos, size_t stop, bool resume,
                  const std::function<bool(std::string_view)>& counts, std::vector<Met>& out) {
  Scanner scan(bytes);
  scan.pos = pos;
  auto giveUp = [&] { out.push_back({scan.pos, Met::GiveUp}); };
  for (;;) {
    scan.skipSpace();
    if (scan.done()) return giveUp();
    if (scan.at("<!--")) {
      if (!scan.skipPast("-->")) return giveUp();
      continue;
    }
    if (scan.at("</")) {  // the root's end tag
      out.push_back({scan.pos, Met::EndTag});
      if (!resume || !scan.skipPast(">")) return;
      out.push_back({scan.pos, Met::Resumed});
      continue;
    }
    if (!scan.at("<") || scan.at("<!") || scan.at("<?")) return giveUp();
    const bool counted = counts && counts(scan.name());
    if (!scan.element()) return giveUp();
    out.push_back({scan.pos, counted ? Met::CountedChild : Met::Child});
    if (scan.pos >= stop) return;
  }
}

// Where a scan of the part of the body from `from` on may start: just after the first '>'
// (at or after from - 1) that is followed, after any space, by the start of an element. As a
// rule that is between two children of the root, or between two children of one of them.
size_t guessBetweenChildren(std::string_view bytes, size_t from, size_t to) {
  for (size_t i = from == 0 ? 0 : from - 1; i < to; ++i) {
    if (bytes[i] != '>') continue;
    size_t j = i + 1;
    while (j < bytes.size() && (bytes[j] == ' ' || bytes[j] == '\t' || bytes[j] == '\r' || bytes[j] == '\n')) ++j;
    if (j + 1 < bytes.size() && bytes[j] == '<' && bytes[j + 1] != '/' && bytes[j + 1] != '!' && bytes[j + 1] != '?')
      return i + 1;
  }
  return std::string_view::npos;
}

}  // namespace

std::optional<XmlSplit> splitXmlRoot(std::string_view bytes, size_t pieceBytes,
                                     const std::function<bool(std::string_view name)>& counts, size_t partBytes) {
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
  // The body is scanned in parts, on every thread: each part from a guessed place between
  // two children (the first from the body's start), until a child ends past the part. Then
  // the scans are joined in order: the scan of the part before ends where the true scan is,
  // and from there on the next part's scan is the true one if it passed the same place (the
  // scan carries nothing else from one child to the next); if it did not, that part is
  // scanned again from there. So the cut is the same for any parts and any number of threads.
  if (partBytes == 0) {
    const size_t threads = size_t(std::max(1, threadBudget()));
    // (One thread scans in parts too: between parts it looks for a signal.)
    partBytes = std::max(size_t(1) << 20, (bytes.size() - split.bodyBegin) / (4 * threads));
  }
  partBytes = std::max<size_t>(partBytes, 1);
  const size_t body = bytes.size() - split.bodyBegin;
  const size_t parts = body == 0 ? 0 : 1 + (body - 1) / partBytes;
  auto partEnd = [&](size_t i) { return i + 1 >= parts ? bytes.size() : split.bodyBegin + (i + 1) * partBytes; };
  std::vector<size_t> starts(parts);
  std::vector<std::vector<Met>> met(parts);
  parallelIndices(parts, 0, [&](size_t i) {
    if (interrupt::requested()) return;  // checked after the loop
    starts[i] = i == 0 ? split.bodyBegin : guessBetweenChildren(bytes, split.bodyBegin + i * partBytes, partEnd(i));
    if (starts[i] == std::string_view::npos) return;
    met[i].reserve((partEnd(i) - starts[i]) / 128);
    scanChildren(bytes, starts[i], partEnd(i), i > 0, counts, met[i]);
  });
  interrupt::check();

  XmlPiece piece{scan.pos, scan.pos};
  size_t at = split.bodyBegin;  // where the true scan is: between two children
  size_t lastChildEnd = 0;
  std::vector<Met> again;
  for (size_t i = 0; i < parts && split.bodyEnd == 0; ++i) {
    if (at >= partEnd(i)) continue;  // a child reached past this part
    // Where this part's scan passed `at`: from there on it is the true scan.
    const std::vector<Met>* events = &met[i];
    size_t from = 0;
    if (starts[i] != at) {
      const auto same = std::find_if(events->begin(), events->end(), [&](const Met& m) {
        return m.pos() == at && m.kind() != Met::EndTag && m.kind() != Met::GiveUp;
      });
      if (same != events->end()) {
        from = size_t(same - events->begin()) + 1;
      } else {
        again.clear();
        scanChildren(bytes, at, partEnd(i), false, counts, again);
        events = &again;
      }
    }
    for (size_t k = from; k < events->size(); ++k) {
      const Met& m = (*events)[k];
      if (m.kind() == Met::GiveUp) return std::nullopt;
      if (m.kind() == Met::EndTag) {
        split.bodyEnd = m.pos();
        break;
      }
      // A child (Resumed never follows on the true scan: an end tag ends it).
      if (m.kind() == Met::CountedChild) ++piece.counted;
      ++split.elements;
      at = lastChildEnd = m.pos();
      if (at - piece.begin >= pieceBytes) {
        piece.end = at;
        split.pieces.push_back(piece);
        piece = {at, at};
      }
      if (at >= partEnd(i)) break;
    }
  }
  if (split.bodyEnd == 0) return std::nullopt;  // (the scan of the last part ends in an end tag or gives up)
  // What follows the last cut joins the last piece when it holds no element: tinyxml2
  // refuses a document of nothing but space.
  if (piece.begin == lastChildEnd && !split.pieces.empty()) {
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
