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

class MappedFile;

// Larger scene files are refused rather than read (a FIFO could otherwise feed bytes for ever).
inline constexpr size_t kMaxSceneBytes = size_t(1) << 30;

// The whole file, or pvrt::Error(SceneError) saying why it cannot be read. Only regular
// files and pipes are read (a directory or a device such as /dev/zero is refused).
std::string readSceneBytes(const std::string& path);

// The bytes of a scene file, as readSceneBytes() gives them; but a big regular file is
// mapped (core/mapped_file.h), its pages taken from the page cache by the threads that read
// them, rather than copied into fresh memory that the kernel must clear first (243 MB: 0.26-0.66 s
// on the 2-core VM, against 0.04 s mapped).
class SceneBytes {
 public:
  enum class Way { MapBigFiles, Read };
  explicit SceneBytes(const std::string& path, Way way = Way::MapBigFiles);
  ~SceneBytes();
  SceneBytes(const SceneBytes&) = delete;
  SceneBytes& operator=(const SceneBytes&) = delete;

  std::string_view view() const;
  // Gives the memory of the whole pages within view()'s [begin, end) back to the system (a
  // mapped file's pages are read again if needed). Only a big file's pages are given back; true
  // when some were. Several threads may give back disjoint ranges at once.
  bool release(size_t begin, size_t end);
  // Whether view() still holds the file as it was when opened: false when a mapped file shrank
  // (its lost pages read as zeros) or grew while it was read. Then it must be read again.
  bool intact() const;

 private:
  std::unique_ptr<MappedFile> mapped_;  // a big file's bytes
  int fd_ = -1;                         // the mapped file's, to see whether it grew
  std::string text_;                    // any other file's
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

// Whether every closing tag of `bytes`, a whole document, closes the element open innermost:
// tinyxml2 parses a document with one outside every element (</scene> twice) as if it ended
// there, without an error.
bool closesOnlyOpenElements(std::string_view bytes);

}  // namespace pvrt
