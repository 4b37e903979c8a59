// text.hpp: names and texts from files and command lines, made safe to quote in a one-line
// message (no control characters reach the terminal, no line is unbounded).
#include "geobrush/text.hpp"

#include <gtest/gtest.h>

using namespace geobrush;

TEST(Text, EscapesControlCharactersAndNul) {
  const std::string text("a\nb\tc\rd\x1b[31m\0e\x7f", 15);
  EXPECT_EQ(escapeText(text), "a\\nb\\tc\\rd\\x1b[31m\\x00e\\x7f");
  // A backslash in the text is told apart from one that starts an escape.
  EXPECT_EQ(escapeText("C:\\x00"), "C:\\\\x00");
  EXPECT_EQ(quoteText("it's\n"), "'it's\\n'");
  EXPECT_EQ(quotePath("/tmp/a\nb.obj"), "'/tmp/a\\nb.obj'");
}

TEST(Text, KeepsValidUtf8) {
  // Two-, three- and four-byte characters, and U+00A0, the first character above the C1 controls.
  const std::string text =
      "B\xC3\xBChne \xE2\x82\xAC \xE6\x97\xA5\xE6\x9C\xAC \xF0\x9F\x98\x80 \xC2\xA0.";
  EXPECT_EQ(escapeText(text), text);
  EXPECT_EQ(messageLine(text), text);
}

TEST(Text, EscapesInvalidUtf8AndC1Controls) {
  EXPECT_EQ(escapeText("\xC2\x85"), "\\xc2\\x85");  // U+0085 NEL, a C1 control
  EXPECT_EQ(escapeText("\xC2\x9B"
                       "31m"),
            "\\xc2\\x9b31m");                                         // U+009B CSI
  EXPECT_EQ(escapeText("\xFF"), "\\xff");                             // never a UTF-8 byte
  EXPECT_EQ(escapeText("\xE2\x82"), "\\xe2\\x82");                    // a character cut short
  EXPECT_EQ(escapeText("\xC0\xAF"), "\\xc0\\xaf");                    // an overlong '/'
  EXPECT_EQ(escapeText("\xED\xA0\x80"), "\\xed\\xa0\\x80");           // a UTF-16 surrogate
  EXPECT_EQ(escapeText("\xF4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
  EXPECT_EQ(escapeText("\x80"
                       "a"),
            "\\x80a");  // a lone continuation byte
}

TEST(Text, CutsAtTheLimitAndSaysHowLongTheTextWas) {
  EXPECT_EQ(escapeText(std::string(1000, 'x'), 10), "xxxxxxxxxx... (1000 bytes)");
  EXPECT_EQ(escapeText(std::string(10, 'x'), 10), "xxxxxxxxxx");
  std::string cut(kExcerptLimit, 'y');
  cut += "... (";
  cut += std::to_string(kExcerptLimit + 1);
  cut += " bytes)";
  EXPECT_EQ(escapeText(std::string(kExcerptLimit + 1, 'y')), cut);
  // The limit counts characters: a UTF-8 character or an escape is one.
  EXPECT_EQ(escapeText("\xE2\x82\xAC\xE2\x82\xAC\xE2\x82\xAC", 2),
            "\xE2\x82\xAC\xE2\x82\xAC... (9 bytes)");
  EXPECT_EQ(escapeText("\n\n\n", 2), "\\n\\n... (3 bytes)");
  EXPECT_EQ(quoteText(std::string(300, 'z'), 3), "'zzz... (300 bytes)'");
}

TEST(Text, MessageLineIsOneBoundedLineThatKeepsItsQuotedEscapes) {
  // The quoted parts of a message are escaped already: their backslashes stay as they are.
  const std::string message = "graph.json: node " + quoteText("a\nb") + ": failed\n";
  EXPECT_EQ(messageLine(message), "graph.json: node 'a\\nb': failed\\n");
  const std::string line = messageLine(std::string(100000, 'm'));
  std::string cut(2000, 'm');
  cut += "... (100000 bytes)";
  EXPECT_EQ(line, cut);
  EXPECT_EQ(line.find('\n'), std::string::npos);
}

TEST(Text, TellsWellFormedUtf8) {
  EXPECT_TRUE(isUtf8("plain \t text"));
  EXPECT_TRUE(isUtf8("t\xc3\xaate \xe2\x82\xac \xf0\x9f\x99\x82 \xc2\x85"));
  EXPECT_FALSE(isUtf8("\xff"));
  EXPECT_FALSE(isUtf8("\xc3"));              // cut short
  EXPECT_FALSE(isUtf8("\xc0\xaf"));          // overlong
  EXPECT_FALSE(isUtf8("\xed\xa0\x80"));      // a surrogate
  EXPECT_FALSE(isUtf8("\xf4\x90\x80\x80"));  // beyond U+10FFFF
}
