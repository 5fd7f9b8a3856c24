#include "scene/xml_document.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"

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
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(f.fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw fail(std::strerror(errno));
    if (n == 0) break;
    if (bytes.size() + size_t(n) > kMaxSceneBytes) throw fail("the file is larger than 1 GiB");
    bytes.append(buf, size_t(n));
  }
  return bytes;
}

size_t firstNonTextByte(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const size_t n = s.size();
  for (size_t i = 0; i < n;) {
    const unsigned char c = p[i];
    if (c < 0x80) {
      if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') return i;
      ++i;
      continue;
    }
    // Lead byte: the sequence length and the smallest code point it may encode (to refuse
    // overlong forms); surrogates and values above U+10FFFF are refused too.
    int len;
    unsigned cp;
    if (c >= 0xc2 && c <= 0xdf) len = 2, cp = c & 0x1f;
    else if (c >= 0xe0 && c <= 0xef) len = 3, cp = c & 0x0f;
    else if (c >= 0xf0 && c <= 0xf4) len = 4, cp = c & 0x07;
    else return i;
    if (i + size_t(len) > n) return i;
    for (int k = 1; k < len; ++k) {
      if ((p[i + k] & 0xc0) != 0x80) return i;
      cp = (cp << 6) | (p[i + k] & 0x3f);
    }
    static const unsigned minimum[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < minimum[len] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return i;
    i += size_t(len);
  }
  return std::string_view::npos;
}

void parseDocument(tinyxml2::XMLDocument& doc, std::string_view bytes, const std::string& name) {
  if (const size_t bad = firstNonTextByte(bytes); bad != std::string_view::npos) {
    const int line = 1 + int(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(bad), '\n'));
    const auto c = static_cast<unsigned char>(bytes[bad]);
    throw sceneError({name, line}, "xml",
                     c < 0x80 ? "control character " + hexByte(c) + " is not allowed (is this a binary file?)"
                              : "byte " + hexByte(c) + " is not UTF-8 text (save the file as UTF-8)");
  }
  if (doc.Parse(bytes.data(), bytes.size()) == tinyxml2::XML_SUCCESS) return;
  const int line = std::max(1, doc.ErrorLineNum());
  std::string what;
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: what = "the file is empty"; break;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      what = "elements nested more than " + std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) + " deep";
      break;
    default: what = std::string("malformed XML (") + doc.ErrorName() + ")";
  }
  throw sceneError({name, line}, "xml", what);
}

}  // namespace pvrt
