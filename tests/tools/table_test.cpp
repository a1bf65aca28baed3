// Column alignment of text and Markdown tables.
#include "report/table.hpp"

#include <gtest/gtest.h>

#include "beamtrace/error.hpp"

namespace beamtrace::report {
namespace {

TEST(Table, TextAlignsColumns) {
    Table t({"scene", "rays", "speed"});
    t.add_row({"bunny", "1000", "12.5 Mrays/s"});
    t.add_row({"sponza", "25", "3.1 s"});
    t.add_row({"x", "-7.5e3", "n/a"});
    EXPECT_EQ(t.rows(), 3u);
    EXPECT_EQ(t.columns(), 3u);
    EXPECT_EQ(t.text(),
              "scene     rays  speed\n"
              "------  ------  ------------\n"
              "bunny     1000  12.5 Mrays/s\n"
              "sponza      25  3.1 s\n"
              "x       -7.5e3  n/a\n");
}

TEST(Table, Markdown) {
    Table t({"name", "n"});
    t.add_row({"a|b", "5"});
    t.add_row({"longer name", "12%"});
    EXPECT_EQ(t.markdown(),
              "| name        |   n |\n"
              "| :---------- | --: |\n"
              "| a\\|b        |   5 |\n"
              "| longer name | 12% |\n");
}

TEST(Table, Utf8WidthsAndEmptyTable) {
    Table t({"µs", "what"});
    t.add_row({"1.5", "ä"});
    EXPECT_EQ(t.text(),
              " µs  what\n"
              "---  ----\n"
              "1.5  ä\n");
    Table empty({"only"});
    EXPECT_EQ(empty.text(), "only\n----\n");
}

TEST(Table, Errors) {
    EXPECT_THROW(Table({}), Error);
    Table t({"a", "b"});
    EXPECT_THROW(t.add_row({"1"}), Error);
    EXPECT_THROW(t.add_row({"1", "2", "3"}), Error);
}

TEST(Table, NumericCells) {
    EXPECT_TRUE(looks_numeric("12"));
    EXPECT_TRUE(looks_numeric("-3.5"));
    EXPECT_TRUE(looks_numeric("1e6"));
    EXPECT_TRUE(looks_numeric("42%"));
    EXPECT_TRUE(looks_numeric("3.1 s"));
    EXPECT_TRUE(looks_numeric("2.5x"));
    EXPECT_FALSE(looks_numeric(""));
    EXPECT_FALSE(looks_numeric("abc"));
    EXPECT_FALSE(looks_numeric("1/2"));
    EXPECT_FALSE(looks_numeric("12 apples"));
    EXPECT_EQ(display_width("µs"), 2u);
}

}  // namespace
}  // namespace beamtrace::report
