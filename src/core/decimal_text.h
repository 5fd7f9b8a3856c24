// Numbers on the command line read as the scene format reads them (docs/scene-format.md,
// "Values"): in decimal digits. C's strtol, which CLI11 2.1 reads integers with (base 0),
// takes "0x10" as 16, "010" as the octal 8 and " 8" as 8, so `--spp 0x10` rendered 16
// samples and `-W 010` an image 8 pixels wide. Here the first and last are refused and
// "010" is ten.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace pvrt {

// `text` as a whole number in decimal digits with an optional '-' (no '+', spaces, base
// prefix or fraction), rewritten without leading zeros so that strtol reads it as written
// ("010" -> "10", "-007" -> "-7", "-0" -> "0"); nothing when it is not one. Its range is
// left to the option's own check.
std::optional<std::string> canonicalWholeNumber(std::string_view text);

// Whether all of `text` is one decimal floating-point number: an optional '+' or '-', digits
// with an optional fraction and exponent ("2", "-0.5", ".25", "1e-3"), or a word std::from_chars
// reads ("inf", "nan": the options' own range checks refuse those with their own messages). No
// hexadecimal ("0x1p3", which strtod reads), spaces, units or second sign.
bool isDecimalNumber(std::string_view text);

}  // namespace pvrt
