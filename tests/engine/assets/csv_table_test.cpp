#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "engine/assets/csv_table.hpp"

using namespace ikebana::assets;

TEST(CsvTable, ReadsHeaderCommentsNumbersAndText) {
    const auto t = parse_csv("# measured 2026-11-01\n"
                             "flower_id,insertion,max_force_gf,room\n"
                             "A,1,484,dry\n"
                             "\n"
                             "A,2,460,\"humid, warm\"\n",
                             "m.csv");
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(t->rows(), 2u);
    EXPECT_EQ(t->line_of_row[1], 5u);
    ASSERT_NE(t->find("max_force_gf"), nullptr);
    ASSERT_TRUE(t->find("max_force_gf")->numeric());
    EXPECT_EQ((*t->find("max_force_gf")->numbers)[1], 460.0);
    EXPECT_FALSE(t->find("flower_id")->numeric()) << "letters: categorical";
    EXPECT_EQ(t->find("room")->text[1], "humid, warm");
}

TEST(CsvTable, EmptyCellsInANumericColumnAreMissing) {
    const auto t = parse_csv("x,y\n1,2\n,3\n", "e.csv");
    ASSERT_TRUE(t);
    ASSERT_TRUE(t->find("x")->numeric());
    EXPECT_TRUE(std::isnan((*t->find("x")->numbers)[1]));
}

TEST(CsvTable, ErrorsNameFileLineAndColumn) {
    const auto fields = parse_csv("a,b,c\n1,2,3\n1,2\n", "f.csv");
    ASSERT_FALSE(fields);
    EXPECT_EQ(fields.error().message, "f.csv:3:1: expected 3 fields (as the header), found 2");
    const auto quote = parse_csv("a,b\n1,\"open\n", "q.csv");
    ASSERT_FALSE(quote);
    EXPECT_EQ(quote.error().message, "q.csv:2:3: unterminated quote (its field runs to the end of the file)");
    const auto twice = parse_csv("a,b,a\n", "d.csv");
    ASSERT_FALSE(twice);
    EXPECT_EQ(twice.error().message, "d.csv:1:5: column 'a' appears twice");
    EXPECT_FALSE(parse_csv("# only a comment\n", "c.csv"));
    EXPECT_FALSE(load_csv("/nonexistent/data.csv"));
}

TEST(CsvTable, MutatedFilesNeverCrashAndRowsStayRectangular) {
    const std::string original = "flower_id,insertion,max_force_gf,note\nA,1,484,\"x, y\"\nA,2,460,z\nB,1,470,\n";
    std::mt19937_64 rng(5);
    const std::string alphabet = ",\"\n#0123456789.e-ab ";
    for (int i = 0; i < 20000; ++i) {
        std::string text = original;
        for (int k = 0; k < 3 && !text.empty(); ++k) {
            const auto at = rng() % text.size();
            if (rng() % 2) text[at] = alphabet[rng() % alphabet.size()];
            else text.erase(at, 1 + rng() % 3);
        }
        const auto t = parse_csv(text, "m.csv");
        if (!t) {
            ASSERT_EQ(t.error().message.rfind("m.csv", 0), 0u);
            continue;
        }
        for (const auto& c : t->columns) {
            ASSERT_EQ(c.text.size(), t->rows());
            if (c.numbers) {
                ASSERT_EQ(c.numbers->size(), t->rows());
            }
        }
    }
}

// Limits a user can see: a table too wide or too long is refused, saying which limit and where.
TEST(CsvTable, TablesBeyondTheLimitsAreRefusedSayingWhich) {
    std::string wide;
    for (std::size_t c = 0; c <= max_csv_columns; ++c) wide += (c ? ",c" : "c") + std::to_string(c);
    const auto too_wide = parse_csv(wide + "\n", "wide.csv");
    ASSERT_FALSE(too_wide);
    EXPECT_EQ(too_wide.error().message, "wide.csv:1:1: 1001 columns, more than the 1000 a table may have here");
    std::string tall = "a\n";
    tall.reserve(2 * max_csv_rows + 16);
    for (std::size_t r = 0; r <= max_csv_rows; ++r) tall += "1\n";
    const auto too_tall = parse_csv(tall, "tall.csv");
    ASSERT_FALSE(too_tall);
    EXPECT_EQ(too_tall.error().message, "tall.csv:1000002:1: more than 1000000 rows, the most a table may have here");
    // The cells' budget (rows x columns), here a small one: refused at the row that passes it.
    const auto too_many = parse_csv("a,b,c\n1,2,3\n4,5,6\n7,8,9\n", "cells.csv", 8);
    ASSERT_FALSE(too_many);
    EXPECT_EQ(too_many.error().message, "cells.csv:4:1: more than 8 cells (rows x columns), the most a table may hold here (about 0 MiB in memory); split the file");
    EXPECT_TRUE(parse_csv("a,b,c\n1,2,3\n4,5,6\n", "cells.csv", 6)) << "exactly at the budget";
}

TEST(CsvTable, AByteOrderMarkAndAnyLineEndingReadAsPlainLines) {
    // Excel's "CSV UTF-8" starts with a BOM (the first column was once "\xEF\xBB\xBFflower_id"), and old
    // Mac exports end lines with a lone CR (once one line, and a misleading duplicate-column error).
    for (const char* text : {"\xEF\xBB\xBF" "flower_id,insertion\nA,1\nB,2\n", "flower_id,insertion\rA,1\rB,2\r",
                             "flower_id,insertion\r\nA,1\r\nB,2", "\xEF\xBB\xBF" "flower_id,insertion\rA,1\n\rB,2\r\n"}) {
        const auto t = parse_csv(text, "lab.csv");
        ASSERT_TRUE(t) << t.error().message;
        ASSERT_NE(t->find("flower_id"), nullptr) << "the first column keeps its name";
        ASSERT_EQ(t->rows(), 2u);
        EXPECT_EQ(t->find("flower_id")->text[1], "B");
        EXPECT_EQ((*t->find("insertion")->numbers)[1], 2.0);
    }
    const auto lines = split_lines("a\r\nb\rc\nd");
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[0].ending, "\r\n");
    EXPECT_EQ(lines[1].ending, "\r");
    EXPECT_EQ(lines[3].text, "d");
    EXPECT_EQ(lines[3].ending, "");
}

// RFC 4180 as spreadsheets write it: a cell with Enter in it is quoted and holds the line break. Its
// row is read whole, the rows after it keep their own line numbers (the file's physical lines), and
// commas, doubled quotes, UTF-8, CRLF and a byte-order mark in the same file still work.
TEST(CsvTable, QuotedLineBreaksStayInTheirCellAndLinesStayPhysical) {
    const auto t = parse_csv("\xEF\xBB\xBF"
                             "flower_id,insertion,max_force_gf,note\r\n"
                             "A,1,484,\"Zoe\r\nNakamura\"\r\n"
                             "A,2,460,\"said \"\"ok\"\", then left\"\r\n"
                             "B,1,470,\"Zoë\n\n, x\"\n"
                             "B,2,455,plain\n",
                             "m.csv");
    ASSERT_TRUE(t) << t.error().message;
    ASSERT_EQ(t->rows(), 4u);
    EXPECT_EQ(t->find("note")->text[0], "Zoe\r\nNakamura");
    EXPECT_EQ(t->find("note")->text[1], "said \"ok\", then left");
    EXPECT_EQ(t->find("note")->text[2], "Zoë\n\n, x");
    EXPECT_EQ(t->line_of_row, (std::vector<std::size_t>{2, 4, 5, 8}));
    EXPECT_EQ(t->last_line_of_row, (std::vector<std::size_t>{3, 4, 7, 8}));
    EXPECT_TRUE(t->note.empty());
    // An error after a cell with line breaks names the physical line it is on.
    const auto bad = parse_csv("a,b\n1,\"x\ny\"\n2,3,4\n", "b.csv");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().message, "b.csv:4:1: expected 2 fields (as the header), found 3");
    const auto after = parse_csv("a,b\n1,\"x\ny\"z\n", "z.csv");
    ASSERT_FALSE(after);
    EXPECT_EQ(after.error().message, "z.csv:3:3: expected ',' after a quoted field");
}

// A row wider than the header is refused as soon as it is, with its count, without keeping its cells:
// a row of 8 million commas (the was 67 million: 2.7 GB as cells) is counted, not split.
TEST(CsvTable, ARowWiderThanTheHeaderIsRefusedWithoutKeepingItsCells) {
    std::string text = "a,b,c\n";
    text += std::string(8'000'000, ',');
    text += "\n";
    const auto t = parse_csv(text, "wide.csv");
    ASSERT_FALSE(t);
    EXPECT_EQ(t.error().message, "wide.csv:2:1: expected 3 fields (as the header), found 8000001");
}

// A file that is not UTF-8 (a spreadsheet's Latin-1 or Windows-1252 export) is read as Windows-1252,
// and the table says so, naming the first such byte's line and column.
TEST(CsvTable, AFileThatIsNotUtf8IsReadAsWindows1252WithANote) {
    const auto t = parse_csv("flower_id,lot\nF1,ok\nF2,Zo\xeb \x80\n", "lab.csv");
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(t->find("lot")->text[1], "Zoë €");
    EXPECT_EQ(t->note, "lab.csv:3:6: byte 0xEB is not UTF-8: the file is read as Windows-1252 (Latin-1), as spreadsheets write it");
    const auto fine = parse_csv("flower_id,lot\nF1,Zoë\n", "utf8.csv");
    ASSERT_TRUE(fine);
    EXPECT_TRUE(fine->note.empty());
    EXPECT_EQ(fine->find("lot")->text[0], "Zoë");
}
