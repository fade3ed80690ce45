// The study's text formatting: numbers, CSV fields and Markdown tables.
#include <gtest/gtest.h>

#include "study/output.h"

namespace tissu {
namespace {

TEST(Output, NumbersWithSignificantDigitsOrAPrintfConversion) {
  EXPECT_EQ(sig(0.000123456), "0.000123");
  EXPECT_EQ(sig(1234567.0, 6), "1.23457e+06");
  EXPECT_EQ(printf_text("%.3f", 2.0), "2.000");
  EXPECT_EQ(printf_text("%.1e", -0.25), "-2.5e-01");
}

TEST(Output, CsvFieldsAreQuotedOnlyWhenNeeded) {
  EXPECT_EQ(csv_field("plain text"), "plain text");
  EXPECT_EQ(csv_field("a, b"), "\"a, b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
}

TEST(Output, MarkdownTableHasHeaderSeparatorRowsAndABlankLine) {
  MarkdownTable t({"a", "b"});
  t.row({"1", "2"});
  t.row({"3", "4"});
  EXPECT_EQ(t.text(), "| a | b |\n| --- | --- |\n| 1 | 2 |\n| 3 | 4 |\n\n");
}

}  // namespace
}  // namespace tissu
