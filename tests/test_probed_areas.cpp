// Session 13's probes (scripts/mutate.sh, s13_): slips the lead listed in product files no mutant
// had touched, to find where the tests were thin. For each probe that survived, a test whose
// expected values are worked by hand here.
#include <gtest/gtest.h>

#include <string>

#include "epuck2/logs/json_location.hpp"

namespace test_probed_areas_cpp {
namespace {

std::string at(const std::string& text, const std::string& pointer) {
  const epuck2::logs::SourcePos p = epuck2::logs::locate_json_pointer(text, pointer);
  return std::to_string(p.line) + ":" + std::to_string(p.column);
}

// A file written on Windows: a byte-order mark, then CRLF line ends. The BOM is skipped (the JSON
// starts after it) and each CRLF ends one line; columns count bytes from the line's start (the
// BOM's three on line 1). Worked by hand: line 2 is `  "kind": "x",`, its value at column 11;
// line 4 is ` 2]`, the element at column 2.
TEST(JsonLocationProbe, AByteOrderMarkAndWindowsLineEnds) {
  const std::string text = "\xEF\xBB\xBF{\r\n  \"kind\": \"x\",\r\n  \"a\": [1,\r\n 2]\r\n}\r\n";
  EXPECT_EQ(at(text, ""), "1:4");
  EXPECT_EQ(at(text, "/kind"), "2:11");
  EXPECT_EQ(at(text, "/a"), "3:8");
  EXPECT_EQ(at(text, "/a/1"), "4:2");
  EXPECT_EQ(at(text, "/b"), "0:0");
}

// An old Mac file: lone CRs end lines too. `{` CR ` "k": 1}`: the value at line 2, column 7
// (space 1, quote 2, k 3, quote 4, colon 5, space 6, 1 at 7).
TEST(JsonLocationProbe, LoneCarriageReturnsEndLines) {
  EXPECT_EQ(at("{\r \"k\": 1}", "/k"), "2:7");
  // CR LF is one line end, CR CR two.
  EXPECT_EQ(at("{\r\n\"k\": 1}", "/k"), "2:6");
  EXPECT_EQ(at("{\r\r\"k\": 1}", "/k"), "3:6");
}

}  // namespace
}  // namespace test_probed_areas_cpp
