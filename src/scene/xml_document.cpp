#include "scene/xml_document.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/error.h"
#include "core/mapped_file.h"
#include "core/interrupt.h"
#include "scene/xml_attributes.h"

namespace pvrt {

namespace {

// Closes the descriptor on every path out, including exceptions.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

std::string hexByte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", c);
  return buf;
}

int lineAt(std::string_view bytes, size_t offset) {
  return 1 + int(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(offset), '\n'));
}

}  // namespace

std::string readSceneBytes(const std::string& path) {
  auto fail = [&](const std::string& why) { return sceneFileError(path, "cannot read scene: " + why); };
  // open() then fstat() on the same descriptor, so the checks are about the file read.
  Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (f.fd < 0) throw fail(std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) throw fail(std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw fail("it is a directory");
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) throw fail("not a regular file");
  // O_NONBLOCK only kept open() from waiting for a FIFO's writer; reads should wait.
  ::fcntl(f.fd, F_SETFL, ::fcntl(f.fd, F_GETFL) & ~O_NONBLOCK);
  std::string bytes;
  // A regular file's size is known: room for it up front, so that a file of hundreds of
  // megabytes is not copied into ever bigger buffers (fresh memory each time) as it is read.
  if (S_ISREG(st.st_mode) && st.st_size > 0) bytes.reserve(std::min<size_t>(size_t(st.st_size), kMaxSceneBytes) + 1);
  char buf[1 << 16];
  for (;;) {
    // A pipe may wait for its writer for ever: it is read only once poll() says there is
    // something, waiting at most 50 ms at a time, so that a signal ends the wait.
    interrupt::check();
    if (S_ISFIFO(st.st_mode)) {
      pollfd p{f.fd, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;  // timed out, or a signal (EINTR)
    }
    const ssize_t n = ::read(f.fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw fail(std::strerror(errno));
    if (n == 0) break;
    if (bytes.size() + size_t(n) > kMaxSceneBytes) throw fail("the file is larger than 1 GiB");
    bytes.append(buf, size_t(n));
  }
  return bytes;
}

SceneBytes::SceneBytes(const std::string& path, Way way) {
  // Files below this are read (readSceneBytes), as are pipes and files that cannot be mapped;
  // readSceneBytes also says why a file cannot be read.
  constexpr size_t kBig = size_t(32) << 20;
  if (way == Way::MapBigFiles) {
    Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
    struct stat st {};
    if (f.fd >= 0 && ::fstat(f.fd, &st) == 0 && S_ISREG(st.st_mode) && size_t(st.st_size) >= kBig &&
        size_t(st.st_size) <= kMaxSceneBytes) {
      auto mapped = std::make_unique<MappedFile>(f.fd, size_t(st.st_size));
      if (mapped->ok()) {
        mapped_ = std::move(mapped);
        fd_ = std::exchange(f.fd, -1);
        return;
      }
    }
  }
  text_ = readSceneBytes(path);
}

SceneBytes::~SceneBytes() {
  if (fd_ >= 0) ::close(fd_);
}

std::string_view SceneBytes::view() const { return mapped_ ? mapped_->bytes() : std::string_view(text_); }

bool SceneBytes::release(size_t begin, size_t end) { return mapped_ && mapped_->drop(begin, end); }

bool SceneBytes::intact() const {
  if (!mapped_) return true;
  char past = 0;
  return !mapped_->shrunk() && ::pread(fd_, &past, 1, off_t(mapped_->bytes().size())) == 0;
}

size_t utf8SequenceLength(std::string_view s, size_t i) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const unsigned char c = p[i];
  if (c < 0x80) return 1;
  // Lead byte: the sequence length and the smallest code point it may encode (to refuse
  // overlong forms); surrogates and values above U+10FFFF are refused too.
  size_t len;
  unsigned cp;
  if (c >= 0xc2 && c <= 0xdf) len = 2, cp = c & 0x1f;
  else if (c >= 0xe0 && c <= 0xef) len = 3, cp = c & 0x0f;
  else if (c >= 0xf0 && c <= 0xf4) len = 4, cp = c & 0x07;
  else return 0;
  if (i + len > s.size()) return 0;
  for (size_t k = 1; k < len; ++k) {
    if ((p[i + k] & 0xc0) != 0x80) return 0;
    cp = (cp << 6) | (p[i + k] & 0x3f);
  }
  static const unsigned minimum[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < minimum[len] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return 0;
  return len;
}

namespace {

// The offset of the first byte at or after `i` that is not printable ASCII, tab, line feed or
// carriage return (a control character, or the first byte of a UTF-8 sequence), else s.size():
// 32 bytes at a time, which is nearly all of a scene's text.
size_t skipPlainAscii(std::string_view s, size_t i) {
#if defined(__AVX2__)
  const __m256i space = _mm256_set1_epi8(0x20), tab = _mm256_set1_epi8('\t'), lf = _mm256_set1_epi8('\n'),
                cr = _mm256_set1_epi8('\r');
  for (; i + 32 <= s.size(); i += 32) {
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(s.data() + i));
    // As signed bytes, those from 0x80 up are negative: below 0x20 with the control characters.
    const __m256i low = _mm256_cmpgt_epi8(space, v);
    const __m256i allowed =
        _mm256_or_si256(_mm256_cmpeq_epi8(v, tab), _mm256_or_si256(_mm256_cmpeq_epi8(v, lf), _mm256_cmpeq_epi8(v, cr)));
    const auto flagged = uint32_t(_mm256_movemask_epi8(_mm256_andnot_si256(allowed, low)));
    if (flagged != 0) return i + size_t(std::countr_zero(flagged));
  }
#endif
  return i;
}

}  // namespace

size_t firstNonTextByte(std::string_view s) {
  for (size_t i = skipPlainAscii(s, 0); i < s.size(); i = skipPlainAscii(s, i)) {
    // Eight plain printable ASCII bytes at a time (no byte below 0x20 or above 0x7f) where
    // fewer than 32 are left or AVX2 is not there; the rest byte by byte.
    if (i + 8 <= s.size()) {
      uint64_t w;
      std::memcpy(&w, s.data() + i, 8);
      constexpr uint64_t kHigh = 0x8080808080808080ull, kSpaces = 0x2020202020202020ull;
      if (((w | ((w - kSpaces) & ~w)) & kHigh) == 0) {
        i += 8;
        continue;
      }
    }
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') return i;
    const size_t len = utf8SequenceLength(s, i);
    if (len == 0) return i;
    i += len;
  }
  return std::string_view::npos;
}

size_t firstBadCharacterReference(std::string_view s) {
  if (s.find("&#") == std::string_view::npos) return std::string_view::npos;  // the usual case
  // Only '<' (which may open a comment or CDATA section) and '&' matter: jump between them.
  for (size_t i = s.find_first_of("<&"); i < s.size(); i = s.find_first_of("<&", i + 1)) {
    // References are not decoded inside comments and CDATA sections.
    if (s[i] == '<') {
      for (const auto& [open, close] : {std::pair{"<!--", "-->"}, std::pair{"<![CDATA[", "]]>"}})
        if (s.compare(i, std::strlen(open), open) == 0) {
          i = std::min(s.find(close, i), s.size());
          break;
        }
      continue;
    }
    if (s.compare(i, 2, "&#") != 0) continue;
    const bool hex = i + 2 < s.size() && s[i + 2] == 'x';
    size_t j = i + (hex ? 3 : 2);
    unsigned long cp = 0;
    for (; j < s.size(); ++j) {
      const auto d = static_cast<unsigned char>(s[j]);
      unsigned digit;
      if (std::isdigit(d)) digit = d - '0';
      else if (hex && std::isxdigit(d)) digit = unsigned(std::tolower(d) - 'a' + 10);
      else break;
      cp = std::min(cp * (hex ? 16 : 10) + digit, 0x110000ul);  // capped: too large either way
    }
    if (j >= s.size() || s[j] != ';') continue;  // not a reference: left as text
    // "&#;" and "&#x;" (no digits) are no references either, but tinyxml2 decodes them to
    // nothing, so radius="1&#x;0" read as 10 (blind14): XML's CharRef needs a digit.
    if (j == i + (hex ? 3 : 2)) return i;
    // XML 1.0's Char production.
    const bool ok = cp == 0x9 || cp == 0xa || cp == 0xd || (cp >= 0x20 && cp <= 0xd7ff) ||
                    (cp >= 0xe000 && cp <= 0xfffd) || (cp >= 0x10000 && cp <= 0x10ffff);
    if (!ok) return i;
  }
  return std::string_view::npos;
}

static bool isXmlSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// In the start tag whose name begins at `from`: the offset of an attribute that follows the
// closing quote of the one before it directly (<sphere center="0 0 0"radius="1"/>, which
// tinyxml2 reads as two attributes though XML requires white space between them), else
// npos. `end` gets the offset of the tag's '>' (npos where the file ends first).
static size_t unseparatedAttribute(std::string_view s, size_t from, size_t& end) {
  constexpr size_t npos = std::string_view::npos;
  for (size_t j = from;;) {
    // The next quote before the next '>' (memchr within the tag: the loader's bytes are mostly
    // tags); a '>' inside a quoted value does not end the tag.
    const size_t gt = s.find('>', j);
    const std::string_view rest = s.substr(j, gt == npos ? npos : gt - j);
    const size_t q = std::min(rest.find('"'), rest.find('\''));
    if (q == npos) {
      end = gt;
      return npos;
    }
    j += q;
    const size_t close = s.find(s[j], j + 1);
    if (close == npos) {  // a value never closed: the parser's error
      end = npos;
      return npos;
    }
    j = close + 1;
    if (j < s.size() && !isXmlSpace(s[j]) && s[j] != '/' && s[j] != '>') return j;
  }
}

// Whether s[i] starts the <?xml ...?> declaration with white space before it: XML allows
// nothing before the declaration but a byte order mark, tinyxml2 skips white space.
static bool declarationAt(std::string_view s, size_t i) {
  return s.compare(i, 5, "<?xml") == 0 && i + 5 < s.size() && isXmlSpace(s[i + 5]);
}

static bool declarationAfterSpace(std::string_view s, size_t i) {
  if (!declarationAt(s, i)) return false;
  const size_t from = s.starts_with("\xEF\xBB\xBF") ? 3 : 0;
  if (i <= from) return false;
  return std::all_of(s.begin() + std::ptrdiff_t(from), s.begin() + std::ptrdiff_t(i), isXmlSpace);
}

// Markup tinyxml2 lets through that XML does not allow: white space after '<' ("< sphere/>",
// which tinyxml2 reads as <sphere/>), "--" inside a comment or a comment ending "--->", two
// attributes with no white space between them, and white space before the declaration.
// The offset of the first, with what is wrong; npos when there is none.
static std::pair<size_t, const char*> firstLaxMarkup(std::string_view s) {
  constexpr size_t npos = std::string_view::npos;
  for (size_t i = s.find('<'); i < s.size(); i = s.find('<', i + 1)) {
    if (s.compare(i, 4, "<!--") == 0) {
      const size_t close = s.find("-->", i + 4);
      if (close == npos) break;  // unclosed: the parser's error
      const std::string_view body = s.substr(i + 4, close - (i + 4));
      if (const size_t d = body.find("--"); d != npos)
        return {i + 4 + d, "\"--\" inside a comment (XML does not allow it; write \"- -\")"};
      if (!body.empty() && body.back() == '-') return {close - 1, "a comment ends in \"--->\" (XML does not allow it)"};
      i = close + 2;
    } else if (s.compare(i, 9, "<![CDATA[") == 0) {
      i = std::min(s.find("]]>", i), s.size());
    } else if (s.compare(i, 2, "<?") == 0) {
      if (declarationAfterSpace(s, i))
        return {i, "white space before the <?xml ...?> declaration (it must be the file's first bytes)"};
      // After a comment or inside <scene>, tinyxml2 said "a <?...?> inside an element" (blind12).
      if (declarationAt(s, i) && i > (s.starts_with("\xEF\xBB\xBF") ? 3u : 0u))
        return {i, "the <?xml ...?> declaration may appear only once, first"};
      i = std::min(s.find("?>", i), s.size());
    } else if (i + 1 < s.size() && isXmlSpace(s[i + 1])) {
      return {i, "white space after '<' (an element's name follows '<' directly)"};
    } else if (s.compare(i, 2, "</") == 0) {
      // tinyxml2 reads attributes in a closing tag (</sphere x="1">) and drops them (blind12).
      size_t j = i + 2;
      while (j < s.size() && !isXmlSpace(s[j]) && s[j] != '>') ++j;
      while (j < s.size() && isXmlSpace(s[j])) ++j;
      if (j >= s.size()) break;  // cut short: the parser's error
      if (s[j] != '>') return {j, "a closing tag holds more than its name (</name> takes no attributes)"};
      i = j;
    } else if (i + 1 < s.size() && s[i + 1] != '/' && s[i + 1] != '!') {
      size_t end = npos;
      if (const size_t bad = unseparatedAttribute(s, i + 1, end); bad != npos)
        return {bad, "no white space between two attributes (XML requires it)"};
      if (end == npos) break;
      i = end;
    }
  }
  return {npos, nullptr};
}

bool isSceneText(std::string_view bytes) {
  return firstNonTextByte(bytes) == std::string_view::npos &&
         firstBadCharacterReference(bytes) == std::string_view::npos &&
         firstLaxMarkup(bytes).first == std::string_view::npos;
}

void checkSceneText(std::string_view bytes, const std::string& name) {
  if (const size_t bad = firstNonTextByte(bytes); bad != std::string_view::npos) {
    const auto c = static_cast<unsigned char>(bytes[bad]);
    throw sceneError({name, lineAt(bytes, bad)}, "xml",
                     c < 0x80 ? "control character " + hexByte(c) + " is not allowed (is this a binary file?)"
                              : "byte " + hexByte(c) + " is not UTF-8 text (save the file as UTF-8)");
  }
  if (const size_t bad = firstBadCharacterReference(bytes); bad != std::string_view::npos) {
    const std::string_view ref = bytes.substr(bad, std::min(bytes.find(';', bad) + 1, bad + 16) - bad);
    const bool noDigits = ref == "&#;" || ref == "&#x;";
    throw sceneError({name, lineAt(bytes, bad)}, "xml",
                     "character reference " + std::string(ref) +
                         (noDigits ? " has no digits (XML writes &#N; or &#xH;)" : " is not an XML character"));
  }
  if (const auto [bad, what] = firstLaxMarkup(bytes); bad != std::string_view::npos)
    throw sceneError({name, lineAt(bytes, bad)}, "xml", what);
}

void parseDocument(tinyxml2::XMLDocument& doc, std::string_view bytes, const std::string& name) {
  checkSceneText(bytes, name);
  parseCheckedText(doc, bytes, name);
}

// The first closing tag that does not close the innermost open element, said as "<a> of line M
// is closed by </b> on line N" (or "</b> on line N closes no element"), and that line N; empty text where
// there is none. tinyxml2's MISMATCHED_ELEMENT names only the line of the open element, so a
// closing tag too many deep in a file pointed at <scene> on line 1 (blind11): the error is
// placed on the closing tag's line instead, where the fix is.
struct MismatchedClose {
  std::string text;
  int line = 0;
};
static MismatchedClose firstMismatchedClose(std::string_view s) {
  constexpr size_t npos = std::string_view::npos;
  auto nameAt = [&](size_t from) {
    const size_t to = std::min(s.find_first_of(" \t\r\n/>", from), s.size());
    return s.substr(from, to - from);
  };
  std::vector<std::string_view> open;  // the names of the elements open, innermost last
  std::vector<size_t> openedAt;        // and where their tags start
  for (size_t i = s.find('<'); i < s.size(); i = s.find('<', i + 1)) {
    if (s.compare(i, 4, "<!--") == 0) {
      i = s.find("-->", i + 4);
    } else if (s.compare(i, 9, "<![CDATA[") == 0) {
      i = s.find("]]>", i + 9);
    } else if (s.compare(i, 2, "<?") == 0) {
      i = s.find("?>", i + 2);
    } else if (s.compare(i, 2, "</") == 0) {
      const std::string_view closing = nameAt(i + 2);
      if (!open.empty() && open.back() == closing) {
        open.pop_back();
        openedAt.pop_back();
        continue;  // to the next '<' (the tag's own '>' holds none)
      }
      const int line = lineAt(s, i);
      const std::string tag = "</" + printable(closing) + "> on line " + std::to_string(line);
      if (open.empty()) return {tag + " closes no element", line};
      return {"<" + printable(open.back()) + "> of line " + std::to_string(lineAt(s, openedAt.back())) +
                  " is closed by " + tag,
              line};
    } else if (s.compare(i, 2, "<!") != 0) {
      size_t end = npos;
      if (unseparatedAttribute(s, i + 1, end) != npos) return {};  // refused before parsing
      if (end != npos && s[end - 1] != '/') {
        open.push_back(nameAt(i + 1));
        openedAt.push_back(i);
      }
      i = end;
    }
    if (i == npos) break;
  }
  return {};
}

bool closesOnlyOpenElements(std::string_view bytes) { return firstMismatchedClose(bytes).text.empty(); }

// What a mismatched closing tag is said to be, after the parser's error name.
static std::string mismatchHint(const MismatchedClose& which) {
  if (which.text.ends_with("closes no element")) return ": " + which.text + " (a closing tag too many)";
  const std::string named = which.text.empty() ? "" : which.text + ": ";
  return ": " + named + "an element not closed, or closed with another name";
}

void parseCheckedText(tinyxml2::XMLDocument& doc, std::string_view bytes, const std::string& name) {
  if (doc.Parse(bytes.data(), bytes.size()) == tinyxml2::XML_SUCCESS) {
    // tinyxml2 stops without an error at a closing tag outside every element (</scene> twice),
    // so that what follows it, objects included, was silently dropped (blind13).
    if (const MismatchedClose which = firstMismatchedClose(bytes); !which.text.empty())
      throw sceneError({name, which.line}, "xml",
                       "malformed XML (XML_ERROR_MISMATCHED_ELEMENT" + mismatchHint(which) + ")");
    return;
  }
  int line = std::max(1, doc.ErrorLineNum());
  std::string what;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: what = "the file is empty"; break;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      what = "elements nested more than " + std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) + " deep";
      break;
    default: {
      // tinyxml2's names are terse; say what usually causes the commonest ones.
      std::string hint;
      // The file cut short gives most of them: say so, not only the rarer causes.
      if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_ATTRIBUTE)
        hint = ": an attribute given twice, without quotes or '=', or the file ends inside its value";
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_ELEMENT)
        hint = ": a tag not closed by '>' or '/>', or the file ends inside one";
      else if (const size_t from = bytes.find_first_not_of(" \t\r\n", bytes.starts_with("\xEF\xBB\xBF") ? 3 : 0);
               doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_TEXT && bytes.find('<') == std::string_view::npos &&
               from != std::string_view::npos) {
        // Text and no markup at all (a note, /proc/self/status): there is no <scene> to be after (blind12).
        const size_t to = bytes.find_first_of("\r\n", from);
        throw sceneError({name, lineAt(bytes, from)}, "xml",
                         "not an XML scene: the file holds text (\"" +
                             printable(bytes.substr(from, to == std::string_view::npos ? to : to - from), 20) +
                             "\") and no element");
      } else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_TEXT)
        hint = ": text after the <scene> element, or the file ends before its elements are closed";
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_COMMENT) hint = ": a comment not closed by '-->'";
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_CDATA) hint = ": a CDATA section not closed by ']]>'";
      // "<!-", "<![CDA", "<!DOCTYPE" cut short (blind12)
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_UNKNOWN)
        hint = ": a <!...> not closed by '>', such as a comment or CDATA section cut short at its start";
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_MISMATCHED_ELEMENT) {
        const MismatchedClose which = firstMismatchedClose(bytes);
        if (!which.text.empty()) line = which.line;
        hint = mismatchHint(which);
      } else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING)  // also a file cut short
        hint = ": not XML, or the file ends before its elements are closed";
      else if (doc.ErrorID() == tinyxml2::XML_ERROR_PARSING_DECLARATION)
        hint = ": a <?...?> inside an element (scenes take none), or one not closed by '?>'";
      what = std::string("malformed XML (") + doc.ErrorName() + hint + ")";
    }
  }
  throw sceneError({name, line}, "xml", what);
}

}  // namespace pvrt
