#include "core/decimal_text.h"

#include <algorithm>
#include <charconv>
#include <system_error>

namespace pvrt {

std::optional<std::string> canonicalWholeNumber(std::string_view text) {
  const bool negative = !text.empty() && text.front() == '-';
  std::string_view digits = text.substr(negative ? 1 : 0);
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
  digits.remove_prefix(std::min(digits.find_first_not_of('0'), digits.size() - 1));
  return (negative && digits != "0" ? "-" : "") + std::string(digits);
}

bool isDecimalNumber(std::string_view text) {
  // from_chars takes a '-' but not a '+': one '+' is skipped, and no sign may follow it.
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && text.front() == '-') return false;
  }
  if (text.empty()) return false;
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  // Out of range ("1e999") is still a decimal number: the option's range says what is wrong.
  return end == text.data() + text.size() && (ec == std::errc() || ec == std::errc::result_out_of_range);
}

}  // namespace pvrt
