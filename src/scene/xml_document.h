// The loader's first stage: bytes in, a tinyxml2 document out, or one `file:line: error:`
// pvrt::Error. Refuses what is not text before the XML parser sees it, so a binary file,
// a file in another encoding or a file with NUL bytes gets a clear message.
#pragma once

#include <memory>
#include <string>
#include <string_view>

namespace tinyxml2 {
class XMLDocument;
}

namespace pvrt {

// Larger scene files are refused rather than read (a FIFO could otherwise feed bytes for ever).
inline constexpr size_t kMaxSceneBytes = size_t(1) << 30;

// The whole file, or pvrt::Error(SceneError) saying why it cannot be read. Only regular
// files and pipes are read (a directory or a device such as /dev/zero is refused).
std::string readSceneBytes(const std::string& path);

// The bytes of a scene file, as readSceneBytes() gives them; but a big regular file is read
// by every thread (threadBudget()) a part each, into memory that is not cleared first (a
// std::string is): 243 MB of fresh memory costs about 0.3 s on one core of the 2-core VM.
class SceneBytes {
 public:
  explicit SceneBytes(const std::string& path);
  std::string_view view() const { return data_ ? std::string_view(data_.get(), size_) : std::string_view(text_); }
  // Gives the memory of the whole pages within view()'s [begin, end) back to the system: what
  // they held is gone (they read as zeros). Only a big file's bytes are given back; true when
  // some were. Several threads may give back disjoint ranges at once.
  bool release(size_t begin, size_t end);

 private:
  std::unique_ptr<char[]> data_;  // a big file's bytes
  size_t size_ = 0;
  std::string text_;  // any other file's
};

// The offset of the first byte that is not XML 1.0 text in UTF-8 (a control character
// other than tab, newline and carriage return, or a malformed UTF-8 sequence), else npos.
size_t firstNonTextByte(std::string_view bytes);

// The length of the valid UTF-8 sequence starting at s[i], or 0 when it is not one.
size_t utf8SequenceLength(std::string_view s, size_t i);

// The offset of the first character reference (`&#0;`, `&#xD800;`) to a code point that
// XML does not allow, else npos. tinyxml2 would decode `&#0;` into a NUL that silently cuts
// the attribute value short.
size_t firstBadCharacterReference(std::string_view bytes);

// Whether checkSceneText() would pass `bytes`: a piece of a file, whose check is left to the
// whole file's (for its message) only when it fails.
bool isSceneText(std::string_view bytes);
// Refuses what is not XML text (firstNonTextByte, firstBadCharacterReference) with a
// `file:line:` pvrt::Error; `name` stands for the file in messages.
void checkSceneText(std::string_view bytes, const std::string& name);
// Parses `bytes` into `doc`, or throws a `file:line:` pvrt::Error saying why it cannot.
void parseDocument(tinyxml2::XMLDocument& doc, std::string_view bytes, const std::string& name);
// parseDocument() for bytes that checkSceneText() has passed.
void parseCheckedText(tinyxml2::XMLDocument& doc, std::string_view bytes, const std::string& name);

}  // namespace pvrt
