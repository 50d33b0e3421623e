// UTF-8 validation and printable escaping (text.h).
#include "hybridtest/common/text.h"

#include <gtest/gtest.h>

namespace hybridtest {
namespace {

TEST(Text, ValidUtf8PassesAndInvalidBytesAreLocated) {
  EXPECT_EQ(FindInvalidUtf8("plain ascii\nλ = 2 ✓ 𝄞"), "");
  EXPECT_EQ(FindInvalidUtf8("a: 1\nb: caf\xE9\n"), "line 2, column 7 (byte 0xE9)");
  EXPECT_NE(FindInvalidUtf8("\xC0\xAF"), "");          // overlong '/'
  EXPECT_NE(FindInvalidUtf8("\xED\xA0\x80"), "");      // a surrogate
  EXPECT_NE(FindInvalidUtf8("\xF4\x90\x80\x80"), "");  // above U+10FFFF
  EXPECT_NE(FindInvalidUtf8("\xE2\x9C"), "");          // truncated
  EXPECT_NE(FindInvalidUtf8("\xFF"), "");
}

TEST(Text, PrintableEscapesControlCharactersAndBadBytesOnly) {
  EXPECT_EQ(Printable("name\nforged line\r"), "name\\x0Aforged line\\x0D");
  EXPECT_EQ(Printable("tab\there"), "tab\\x09here");
  EXPECT_EQ(Printable("caf\xE9"), "caf\\xE9");
  EXPECT_EQ(Printable("λ ✓ ok"), "λ ✓ ok");
  EXPECT_EQ(Printable(std::string("a\0b", 3)), "a\\x00b");
}

}  // namespace
}  // namespace hybridtest
