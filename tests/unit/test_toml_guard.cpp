// The guard in front of toml++ 3.3 (src/scene/toml_guard.hpp) refuses only what the library
// cannot parse safely: non-ASCII text in strings and comments still loads.
#include <gtest/gtest.h>

#include "maille/scene.hpp"

namespace maille {
namespace {

TEST(TomlGuard, NonAsciiInStringsAndCommentsLoads) {
  const char* text =
      "\xEF\xBB\xBF# a flag at 20 \xC2\xB0"
      "C, 1.5 m \xC3\x97 1 m, \xD1\xA2\n"
      "[scene]\n"
      "name = \"drapeau\"\n"  // names a directory (ASCII only): the accents go below
      "description = '''drapeau \xC3\xA9t\xC3\xA9 Ѣ \xC2\xA7 multi\nline'''\n"
      "[[mass]]\n"
      "name = \"\xC2\xB5-bead\"\n"
      "position = [0, 0, 0]  # \xC2\xB5m\n"
      "mass = 1.0\n";
  auto scene = parse_scene(text, "utf8.toml", LinkKindRegistry::with_builtins());
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  EXPECT_EQ(scene->description.rfind("drapeau \xC3\xA9t\xC3\xA9", 0), 0u);
}

TEST(TomlGuard, NonAsciiOutsideStringsIsAnInputError) {
  const auto r =
      parse_scene("[[mass]]\nmass = \xC2\xB5\n", "bad.toml", LinkKindRegistry::with_builtins());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().line, 2);
  EXPECT_EQ(r.error().column, 8);
}

}  // namespace
}  // namespace maille
