// A plugin's log line as the host passes it on (core/src/plugins/log_text.hpp):
// capped, its control characters and stray bytes escaped, UTF-8 kept.
#include "../../../core/src/plugins/log_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace mh {
namespace {

TEST(LogText, PrintableTextAndUtf8PassUnchanged) {
  EXPECT_EQ(log_text("p = 7.6 MPa, \xce\x94p \xe2\x89\xa5 0"),
            "p = 7.6 MPa, \xce\x94p \xe2\x89\xa5 0");
  EXPECT_EQ(log_text("\xf0\x9f\x94\xa7 wrench"), "\xf0\x9f\x94\xa7 wrench");
  EXPECT_EQ(log_text(nullptr), "");
  EXPECT_EQ(log_text(""), "");
}

TEST(LogText, ControlCharactersAndEscapeSequencesCannotReachTheTerminal) {
  EXPECT_EQ(log_text("a\nmonohydra: forged\r\tb"), "a\\nmonohydra: forged\\r\\tb");
  EXPECT_EQ(log_text("\x1b[2J\x1b[31mred"), "\\x1b[2J\\x1b[31mred");
  EXPECT_EQ(log_text("back\\slash \x7f"), "back\\\\slash \\x7f");
}

TEST(LogText, BytesThatAreNotUtf8AreEscapedOneByOne) {
  EXPECT_EQ(log_text("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(log_text("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(log_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(log_text("\xe2\x89"), "\\xe2\\x89");                    // cut short
  EXPECT_EQ(log_text("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
}

TEST(LogText, AHugeLineIsCutAtTheLimitAndSaysHowMuchWasLeftOut) {
  const std::string huge(64u << 20, 'x');  // 64 MiB
  const std::string shown = log_text(huge.c_str());
  EXPECT_EQ(shown, std::string(kLogTextLimit, 'x') + "... (" +
                       std::to_string(huge.size() - kLogTextLimit) + " more bytes)");
  const std::string escapes(10000, '\n');
  const std::string cut = log_text(escapes.c_str());
  EXPECT_LE(cut.size(), kLogTextLimit + 40);
  EXPECT_EQ(cut.substr(cut.size() - 17), "(7952 more bytes)");
}

}  // namespace
}  // namespace mh
