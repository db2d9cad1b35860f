#include <gtest/gtest.h>

#include "engine/core/utf8.hpp"

using namespace ikebana;

// Well-formed UTF-8 passes whole; each kind of malformed sequence is found at its first byte.
TEST(Utf8, FindsTheFirstByteThatIsNotUtf8) {
    EXPECT_FALSE(first_non_utf8("Zoë Nakamura, 生け花 🌸"));
    EXPECT_EQ(first_non_utf8("Zo\xeb"), 2u) << "Latin-1's e with diaeresis";
    EXPECT_EQ(first_non_utf8("ab\xff"), 2u);
    EXPECT_EQ(first_non_utf8("\xc3"), 0u) << "a sequence cut short";
    EXPECT_EQ(first_non_utf8("x\xc0\xaf"), 1u) << "an overlong '/'";
    EXPECT_EQ(first_non_utf8("\xed\xa0\x80"), 0u) << "a surrogate";
    EXPECT_EQ(first_non_utf8("\xf4\x90\x80\x80"), 0u) << "past U+10FFFF";
    EXPECT_EQ(*non_utf8_words("--trainee", "Zo\xeb"), "--trainee: not UTF-8 text (byte 0xEB at position 3)");
    EXPECT_FALSE(non_utf8_words("--trainee", "Zoë"));
}

TEST(Utf8, ReplacesWhatIsNotUtf8AndReadsWindows1252) {
    EXPECT_EQ(utf8_or_replacement("Zo\xeb!"), "Zo\xEF\xBF\xBD!");
    EXPECT_EQ(utf8_or_replacement("Zoë"), "Zoë");
    EXPECT_EQ(windows1252_to_utf8("Zo\xeb \x80 \x93quoted\x94 \xff"), "Zoë € “quoted” ÿ");
    EXPECT_TRUE(is_utf8(windows1252_to_utf8(std::string("\x81\x8d\x8f\x90\x9d\x00\x7f", 7)))) << "the five bytes 1252 leaves undefined too";
}

TEST(Utf8, TextFromDataReachesATerminalWithItsControlCharactersShownNotSent) {
    EXPECT_EQ(terminal_text("plain text, caf\xc3\xa9\n\tand a tab"), "plain text, caf\xc3\xa9\n\tand a tab") << "line breaks and tabs stay";
    EXPECT_EQ(terminal_text("\x1b]0;owned\x07title"), "\\x1b]0;owned\\x07title") << "an OSC title change is shown, not sent";
    EXPECT_EQ(terminal_text("\x1b[2J\x1b[H"), "\\x1b[2J\\x1b[H") << "a screen clear";
    EXPECT_EQ(terminal_text("a\xc2\x9b" "31mred"), "a\\x9b31mred") << "the C1 CSI, as UTF-8 encodes it";
    EXPECT_EQ(terminal_text("\x7f\r"), "\\x7f\\x0d");
    EXPECT_EQ(terminal_text("bad \xff byte"), "bad \xef\xbf\xbd byte") << "not UTF-8: U+FFFD";
}
