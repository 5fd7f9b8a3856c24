#include "scene/xml_attributes.h"

#include "scene/separation.h"
#include "scene/xml_document.h"

#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fmt/core.h>

namespace pvrt {

namespace {

// For a number that std::from_chars read whole but found out of range: whether it is too
// large (rather than too small) for a double. Out-of-range magnitudes lie above 1e308 or
// below 1e-323, so the rough decimal exponent (digits before the point, less the zeros
// after it, plus the written exponent) tells them apart.
bool overflows(std::string_view w) {
  if (!w.empty() && w[0] == '-') w.remove_prefix(1);
  const size_t e = std::min(w.find_first_of("eE"), w.size());
  const std::string_view mantissa = w.substr(0, e);
  const size_t point = std::min(mantissa.find('.'), mantissa.size());
  const std::string_view whole = mantissa.substr(0, point);
  long long order = 0;
  if (const size_t nz = whole.find_first_not_of('0'); nz != std::string_view::npos) {
    order = static_cast<long long>(whole.size() - nz);
  } else if (point < mantissa.size()) {
    const std::string_view frac = mantissa.substr(point + 1);
    order = -static_cast<long long>(std::min(frac.find_first_not_of('0'), frac.size()));
  }
  if (e + 1 < w.size()) {
    std::string_view exp = w.substr(e + 1);
    const bool negative = exp[0] == '-';
    if (exp[0] == '-' || exp[0] == '+') exp.remove_prefix(1);
    long long x = 0;
    if (std::from_chars(exp.data(), exp.data() + exp.size(), x).ec != std::errc()) x = 1'000'000'000;
    order += negative ? -std::min(x, 1'000'000'000LL) : std::min(x, 1'000'000'000LL);
  }
  return order > 0;
}

// Edit distance, to suggest the known attribute a misspelt one was meant to be.
size_t distance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string attr(std::string_view name) { return "attribute '" + std::string(name) + "'"; }

// a == b, for attribute names (a few letters): compared here rather than by a call, since an
// element is asked about a dozen names and most differ from a given one in length.
bool sameName(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) return false;
  return true;
}

bool separator(char c) { return c == ' ' || c == ',' || c == '\t' || c == '\n' || c == '\r'; }

// Calls f(word) for every word of `text` (words are separated by spaces, commas, tabs and
// line ends).
template <class F>
void forEachWord(const char* text, F&& f) {
  for (const char* p = text; *p;) {
    if (separator(*p)) {
      ++p;
      continue;
    }
    const char* start = p;
    while (*p && !separator(*p)) ++p;
    f(std::string_view(start, size_t(p - start)));
  }
}

// How many words `text` has; the first `max` of them go to `out`. Without a vector: a big
// scene reads millions of vectors.
size_t wordsIn(const char* text, std::string_view* out, size_t max) {
  size_t n = 0;
  forEachWord(text, [&](std::string_view w) {
    if (n < max) out[n] = w;
    ++n;
  });
  return n;
}

// The code point of one valid UTF-8 sequence of two to four bytes.
unsigned codePoint(std::string_view seq) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(seq[k]); };
  unsigned cp = byte(0) & (0xffu >> (seq.size() + 1));
  for (size_t k = 1; k < seq.size(); ++k) cp = (cp << 6) | (byte(k) & 0x3fu);
  return cp;
}

// Unicode's spaces other than ' ', and the characters of no width: printed, they pass for
// a space or for nothing.
bool invisible(std::string_view seq) {
  const unsigned cp = codePoint(seq);
  return cp == 0xa0 || cp == 0x1680 || (cp >= 0x2000 && cp <= 0x200f) || cp == 0x2028 || cp == 0x2029 || cp == 0x202f ||
         cp == 0x205f || cp == 0x2060 || cp == 0x3000 || cp == 0xfeff;
}

constexpr size_t kNotPlain = size_t(-1);

// How many numbers `text` holds, when it is at most `max` numbers that parseNumber() takes as
// they are (finite, within kMaxSceneNumber, not too small for a double), each read once where
// they lie; kNotPlain for anything else, whose reading and message are left to the word-by-word
// path (wordsIn, parseNumber). A big scene has millions of numbers, nearly all plain.
size_t plainNumbers(const char* text, double* out, size_t max) {
  const char* p = text;
  const char* const end = text + std::strlen(text);
  size_t n = 0;
  for (;;) {
    while (p != end && separator(*p)) ++p;
    if (p == end) return n;
    if (n == max) return kNotPlain;
    const char* const begin = *p == '+' ? p + 1 : p;  // as parseNumber() reads a word
    const auto [next, ec] = std::from_chars(begin, end, out[n]);
    if (ec != std::errc() || (next != end && !separator(*next)) || !std::isfinite(out[n]) ||
        std::fabs(out[n]) > kMaxSceneNumber)
      return kNotPlain;
    ++n;
    p = next;
  }
}

}  // namespace

std::string printable(std::string_view text, size_t max) {
  std::string out;
  size_t i = 0;
  while (i < text.size() && out.size() < max) {
    const auto c = static_cast<unsigned char>(text[i]);
    const size_t len = utf8SequenceLength(text, i);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\r') out += "\\r";
    else if (len > 1 && invisible(text.substr(i, len))) {
      // A space that is not ' ' (a no-break space, say) would read as one in the message.
      char code[16];
      std::snprintf(code, sizeof code, "\\u%04x", codePoint(text.substr(i, len)));
      out += code;
    } else if (c >= 0x20 && c != 0x7f && len > 0) {
      out.append(text.substr(i, len));
    } else {  // a control character, or a byte that is not UTF-8
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
    i += std::max<size_t>(len, 1);
  }
  if (i < text.size()) out += "...";
  return out;
}

std::vector<std::string_view> words(const char* text) {
  std::vector<std::string_view> out;
  forEachWord(text, [&](std::string_view w) { out.push_back(w); });
  return out;
}

Attributes::Attributes(const tinyxml2::XMLElement* e, FileName file,
                       const std::vector<std::string_view>& known, int lineOffset)
    : e_(e), file_(file), lineOffset_(lineOffset) {
  for (const tinyxml2::XMLAttribute* a = e_->FirstAttribute(); a; a = a->Next()) {
    const std::string_view name = a->Name();
    if (std::any_of(known.begin(), known.end(), [&](std::string_view k) { return sameName(k, name); })) {
      // No element knows that many (see named_).
      if (count_ == kMaxAttributes) throw error("more than " + std::to_string(kMaxAttributes) + " attributes");
      named_[size_t(count_++)] = {name.data(), name.size(), a};
      continue;
    }
    std::string what = "unknown attribute '" + printable(name) + "'";
    std::string_view best;
    size_t bestDistance = 3;  // at most two edits away, and closer than any other
    for (std::string_view k : known)
      if (const size_t d = distance(name, k); d < bestDistance && d < k.size()) best = k, bestDistance = d;
    if (!best.empty()) what += " (did you mean '" + std::string(best) + "'?)";
    throw error(what);
  }
}

SourceLoc Attributes::loc() const { return {file_, e_->GetLineNum() + lineOffset_}; }
Error Attributes::error(const std::string& what) const { return sceneError(loc(), printable(e_->Name()), what); }
Error Attributes::missing(std::string_view name) const {
  return error("missing required attribute '" + std::string(name) + "'");
}
std::string Attributes::raw(std::string_view name) const {
  for (int i = 0; i < count_; ++i)
    if (sameName({named_[size_t(i)].name, named_[size_t(i)].size}, name)) return named_[size_t(i)].attribute->Value();
  return {};
}

const tinyxml2::XMLAttribute* Attributes::find(std::string_view name) {
  for (int i = 0; i < count_; ++i) {
    if (sameName({named_[size_t(i)].name, named_[size_t(i)].size}, name)) {
      used_ |= uint64_t(1) << i;
      return named_[size_t(i)].attribute;
    }
  }
  return nullptr;
}

bool Attributes::has(std::string_view name) { return find(name) != nullptr; }

void Attributes::numbers(std::string_view name, double* out, size_t count, const char* what) {
  const tinyxml2::XMLAttribute* a = find(name);
  if (!a) throw missing(name);
  if (plainNumbers(a->Value(), out, count) == count) return;
  std::string_view w[3];
  if (wordsIn(a->Value(), w, count) != count) throw error(attr(name) + what + quoted(name));
  for (size_t i = 0; i < count; ++i) out[i] = parseNumber(name, w[i]);
}

double Attributes::number(std::string_view name) {
  double v;
  numbers(name, &v, 1, " must be one number, got ");
  return v;
}

double Attributes::nonNegative(std::string_view name, double fallback) {
  const double v = number(name, fallback);
  if (v < 0) throw error(attr(name) + " must not be negative, got " + printable(raw(name)));
  return v;
}

double Attributes::positive(std::string_view name, std::optional<double> fallback) {
  if (!fallback && !has(name)) throw missing(name);
  const double v = number(name, fallback.value_or(0));
  if (!(v > 0)) throw error(attr(name) + " must be positive, got " + printable(raw(name)));
  return v;
}

int Attributes::integer(std::string_view name, int fallback, int lo, int hi) {
  if (!has(name)) return fallback;
  const std::string text = raw(name);
  long long v = 0;
  const char* end = text.data() + text.size();
  auto [p, ec] = std::from_chars(text.data(), end, v);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && p == end && (v < lo || v > hi)))
    throw error(attr(name) + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                ", got " + printable(text));
  if (ec != std::errc() || p != end) throw error(attr(name) + " must be an integer, got " + quoted(name));
  return int(v);
}

Vec3 Attributes::vec(std::string_view name) {
  double v[3];
  numbers(name, v, 3, " must be a vector of 3 numbers, got ");
  return {v[0], v[1], v[2]};
}

Vec3 Attributes::nonZeroVec(std::string_view name, std::optional<Vec3> fallback) {
  const Vec3 v = fallback ? vec(name, *fallback) : vec(name);
  if (v == Vec3{}) throw error(attr(name) + " must not be the zero vector");
  if (std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}) < kMinLength)
    throw error(attr(name) + " is too short to give a direction: its components are below " +
                fmt::format("{:g}", kMinLength));
  return v;
}

Vec3 Attributes::vecOrScalar(std::string_view name) {
  const tinyxml2::XMLAttribute* a = find(name);
  if (!a) throw missing(name);
  double v[3];
  const size_t plain = plainNumbers(a->Value(), v, 3);
  if (plain == 1) return Vec3(v[0]);
  if (plain == 3) return {v[0], v[1], v[2]};
  std::string_view w;
  if (wordsIn(a->Value(), &w, 1) == 1) return Vec3(parseNumber(name, w));
  return vec(name);
}

Color Attributes::color(std::string_view name, Color fallback) {
  if (!has(name)) return fallback;
  const Vec3 v = vecOrScalar(name);
  return {v.x, v.y, v.z};
}

bool Attributes::boolean(std::string_view name, bool fallback) {
  if (!has(name)) return fallback;
  const std::string v = raw(name);
  if (v == "true") return true;
  if (v == "false") return false;
  throw error(attr(name) + " must be true or false, got " + quoted(name));
}

std::string Attributes::text(std::string_view name) {
  if (!has(name)) throw missing(name);
  return raw(name);
}

void Attributes::done() const {
  for (int i = 0; i < count_; ++i)
    if (!(used_ >> i & 1u)) throw error("unknown attribute '" + printable({named_[size_t(i)].name, named_[size_t(i)].size}) + "'");
}

double Attributes::parseNumber(std::string_view name, std::string_view w) const {
  double v = 0;
  const char* begin = w.data();
  if (*begin == '+') ++begin;
  const char* end = w.data() + w.size();
  auto [p, ec] = std::from_chars(begin, end, v);
  // from_chars leaves `v` untouched when out of range, so tell underflow (a number too
  // tiny for a double: zero) from overflow (an error) by its decimal exponent.
  if (ec == std::errc::result_out_of_range && p == end && !overflows(std::string_view(begin, end)))
    ec = std::errc();
  if (ec == std::errc() && p == end && std::isfinite(v) && std::fabs(v) <= kMaxSceneNumber) return v;
  // The messages are only built for a bad number (a big scene has millions of good ones).
  const std::string shown = printable(w);
  const std::string range = " is out of range (at most 1e15 in magnitude)";
  if (ec == std::errc::result_out_of_range) throw error(attr(name) + ": " + shown + range);
  if (ec != std::errc() || p != end) throw error(attr(name) + ": \"" + shown + "\" is not a number");
  if (!std::isfinite(v)) throw error(attr(name) + ": " + shown + " is not a finite number");
  throw error(attr(name) + ": " + shown + range);
}

}  // namespace pvrt
