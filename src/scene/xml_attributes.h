// One XML element's attributes read as the value types of docs/scene-format.md (numbers,
// integers, vectors, colours, booleans, names), each checked as it is read. Every problem
// becomes a one-line `file:line: error: element: what` pvrt::Error.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/color.h"
#include "core/error.h"
#include "core/source_loc.h"
#include "core/vec3.h"

namespace tinyxml2 {
class XMLAttribute;
class XMLElement;
}

namespace pvrt {

// The largest magnitude of a number in a scene. Beyond it a double no longer holds whole
// units (2^53 is about 9e15), and squares and products of such numbers inside the
// renderer could overflow to inf and turn into NaN pixels.
inline constexpr double kMaxSceneNumber = 1e15;

// `text` made safe for a one-line message: at most `max` bytes (cut on a character
// boundary, "..." appended), control characters written as \n, \t, \r or \xNN.
std::string printable(std::string_view text, size_t max = 40);

// The words of "1 2 3" or "1, 2, 3", as views into `text`: a big scene has millions of
// numbers, and a word longer than a std::string's inline buffer would cost a heap copy.
std::vector<std::string_view> words(const char* text);

class Attributes {
 public:
  // `known`: every attribute the element may carry. Any other is refused here, before a
  // value is read, so that a misspelt required attribute (`radus`) is reported as the
  // unknown one, together with the name it resembles, not as a missing `radius`.
  // `lineOffset` is added to tinyxml2's line numbers: a piece of a file (scene/xml_split.h)
  // is parsed from its own first line.
  Attributes(const tinyxml2::XMLElement* e, FileName file, const std::vector<std::string_view>& known,
             int lineOffset = 0);

  SourceLoc loc() const;
  Error error(const std::string& what) const;
  Error missing(std::string_view name) const;

  bool has(std::string_view name);
  double number(std::string_view name);
  double number(std::string_view name, double fallback) { return has(name) ? number(name) : fallback; }
  double nonNegative(std::string_view name, double fallback);
  double positive(std::string_view name, std::optional<double> fallback = std::nullopt);
  int integer(std::string_view name, int fallback, int lo, int hi);
  Vec3 vec(std::string_view name);
  Vec3 vec(std::string_view name, Vec3 fallback) { return has(name) ? vec(name) : fallback; }
  Vec3 nonZeroVec(std::string_view name, std::optional<Vec3> fallback = std::nullopt);
  Vec3 vecOrScalar(std::string_view name);  // "x y z", or one number for all three
  Color color(std::string_view name, Color fallback);
  bool boolean(std::string_view name, bool fallback);
  std::string text(std::string_view name);
  // One word of attribute `name` as a number: finite and within kMaxSceneNumber.
  double parseNumber(std::string_view name, std::string_view word) const;

  // Call after reading: an attribute present but not read is unknown in this context.
  void done() const;

 private:
  // The attribute `name`, marked as asked about; nullptr when the element has none.
  const tinyxml2::XMLAttribute* find(std::string_view name);
  // The attribute `name` as `count` numbers (a vector's, or a number's), or refused.
  void numbers(std::string_view name, double* out, size_t count, const char* what);
  std::string raw(std::string_view name) const;
  std::string quoted(std::string_view name) const { return "\"" + printable(raw(name)) + "\""; }

  // An attribute of the element with its name, read once: an element is asked about a dozen
  // names, and a big scene has millions of elements.
  // (A plain aggregate: the array of them below is left unset, not cleared, for each element.)
  struct Named {
    const char* name;
    size_t size;
    const tinyxml2::XMLAttribute* attribute;
  };

  const tinyxml2::XMLElement* e_;
  FileName file_;
  int lineOffset_ = 0;
  // The constructor refuses unknown attributes and XML refuses repeated ones, so an element
  // has no more attributes than its known list, far fewer than 64.
  static constexpr int kMaxAttributes = 64;
  std::array<Named, kMaxAttributes> named_;  // [0, count_) in the element's order
  int count_ = 0;
  // Bit i: named_[i] has been asked about.
  uint64_t used_ = 0;
};

}  // namespace pvrt
