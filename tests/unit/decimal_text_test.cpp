// Command-line numbers are read in decimal digits, as the scene format reads them
// (core/decimal_text.h): CLI11 alone read "0x10" as 16, "010" as 8 and " 8" as 8.
#include "core/decimal_text.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/memory_limit.h"

using namespace pvrt;

TEST(DecimalText, WholeNumbersAreDecimalDigitsWrittenWithoutLeadingZeros) {
  EXPECT_EQ(canonicalWholeNumber("8"), "8");
  EXPECT_EQ(canonicalWholeNumber("640"), "640");
  EXPECT_EQ(canonicalWholeNumber("010"), "10");  // strtol in base 0: octal 8
  EXPECT_EQ(canonicalWholeNumber("-007"), "-7");
  EXPECT_EQ(canonicalWholeNumber("000"), "0");
  EXPECT_EQ(canonicalWholeNumber("-0"), "0");
  EXPECT_EQ(canonicalWholeNumber("-1"), "-1");  // the option's range refuses it, with its own message
  EXPECT_EQ(canonicalWholeNumber("99999999999999999999999"), "99999999999999999999999");
}

TEST(DecimalText, WholeNumbersRefuseHexSpacesSignsAndFractions) {
  for (const char* text : {"0x10", "0X10", " 8", "8 ", "+8", "--8", "-", "", "1.0", "1e3", "8k", "0b1", "１"})
    EXPECT_FALSE(canonicalWholeNumber(text).has_value()) << '"' << text << '"';
}

TEST(DecimalText, DecimalNumbersAreTheSceneFormatsNumbers) {
  for (const char* text : {"0", "0.3", "-0.5", "+2", ".25", "5.", "1e-3", "6.02E23", "1e999", "inf", "nan", "-inf"})
    EXPECT_TRUE(isDecimalNumber(text)) << '"' << text << '"';
  for (const char* text :
       {"0x1p3", "0x0.1p0", " 0.3", "0.3 ", "+-1", "++1", "-+1", "+", "", "1,5", "0.3s", "1e", ".", "1 2"})
    EXPECT_FALSE(isDecimalNumber(text)) << '"' << text << '"';
}

TEST(DecimalText, MemoryLimitsAreDecimal) {
  EXPECT_EQ(parseMemorySize("512M"), size_t(512) << 20);
  EXPECT_EQ(parseMemorySize("1.5K"), size_t(1536));
  EXPECT_EQ(parseMemorySize("100000"), size_t(100000));
  for (const char* text : {"0x100M", " 100M", "100 M", "1e", "infM", "nanK", "-1M", "+1M", "M", ""}) {
    try {
      parseMemorySize(text);
      ADD_FAILURE() << "accepted \"" << text << '"';
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ExitCode::Usage);
      EXPECT_EQ(std::string(e.what()).rfind("pvrt: error: --memory-limit: expected a size", 0), 0u) << e.what();
    }
  }
}
