// Scene errors echo the scene's own bytes; those a terminal would act on are shown as \xNN.
#include "tools/scene/scene_error.h"

#include <gtest/gtest.h>

#include <string>

namespace csim {
namespace {

TEST(PrintableText, ControlBytesAreEscaped) {
  EXPECT_EQ(printable_text("\x1b[31mred\x1b[0m"), "\\x1b[31mred\\x1b[0m");
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable_text("line\r\nnext\ttab\x7f"), "line\\x0d\\x0anext\\x09tab\\x7f");
  EXPECT_EQ(printable_text("\xc2\x9b" "2J"), "\\xc2\\x9b2J");  // U+009B, a CSI to some terminals
}

TEST(PrintableText, ValidUtf8IsKept) {
  EXPECT_EQ(printable_text("μ = 0.3, θ in °, 𝜇"), "μ = 0.3, θ in °, 𝜇");
  EXPECT_EQ(printable_text("plain ASCII: mass=2 [kg] \\ 'quoted'"), "plain ASCII: mass=2 [kg] \\ 'quoted'");
}

TEST(PrintableText, InvalidUtf8IsEscaped) {
  EXPECT_EQ(printable_text("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printable_text("\xce"), "\\xce");                   // μ cut after its first byte
  EXPECT_EQ(printable_text("\xc0\xaf"), "\\xc0\\xaf");          // overlong '/'
  EXPECT_EQ(printable_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a UTF-16 surrogate
  EXPECT_EQ(printable_text("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // above U+10FFFF
}

TEST(SceneErrorMessage, EchoedInputIsPrintable) {
  const SceneError error("scene\x1b.yaml", 4, "bodies.\x1b[31mblock", "got '\x07μ'");
  EXPECT_EQ(std::string(error.what()), "scene\\x1b.yaml:4: bodies.\\x1b[31mblock: got '\\x07μ'");
}

}  // namespace
}  // namespace csim
