#pragma once
// A CSV table as researchers write it: a header row, lines starting with '#' are comments, fields
// separated by commas, optionally quoted ("a, b", "" for a quote, and line breaks inside quotes as
// RFC 4180 and spreadsheets have them). UTF-8, or else read as Windows-1252 with a note. Every column is kept as text
// and, where every non-empty cell parses as a finite number, also as numbers, so that columns the
// program has never heard of can be analysed as numeric or categorical. Errors name the file, the
// line and the column; nothing is returned half read.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::assets {

struct CsvColumn {
    std::string name;
    std::vector<std::string> text;              // every cell as written (unquoted)
    std::optional<std::vector<double>> numbers;  // when every non-empty cell is a number; empty cells are NaN
    [[nodiscard]] bool numeric() const noexcept { return numbers.has_value(); }
};

struct CsvTable {
    std::string label;
    std::vector<CsvColumn> columns;
    std::vector<std::size_t> line_of_row;      // source line where each row begins, for messages about rows
    std::vector<std::size_t> last_line_of_row; // and where it ends (a quoted cell may hold line breaks)
    std::size_t header_last_line = 0;          // the line the header ends on
    std::string note; // how it was read, when not as written (a file that is not UTF-8); empty otherwise
    [[nodiscard]] std::size_t rows() const noexcept { return line_of_row.size(); }
    [[nodiscard]] const CsvColumn* find(std::string_view name) const noexcept;
};

// Limits a table must keep (a lab's file has thousands of rows and tens of columns); each refusal says
// which and where.
inline constexpr std::size_t max_csv_rows = 1'000'000;
inline constexpr std::size_t max_csv_columns = 1'000;
// Rows times columns: the table's memory budget (a cell is held as text and, in a numeric column, as a
// number: about 40 bytes, so some 400 MiB at the limit). A file over it is refused at the row that
// would pass it, before the memory is taken.
inline constexpr std::size_t max_csv_cells = 10'000'000;

// A text's lines as spreadsheets write them: "\n", "\r\n" or a lone "\r" (old Mac exports) ends a
// line, and a UTF-8 byte-order mark before the first is dropped. `ending` is what ended each line
// ("" for the last, unterminated one), so that a tool writing the lines back keeps them.
struct TextLine {
    std::string_view text;
    std::string_view ending;
};
std::vector<TextLine> split_lines(std::string_view text);

Result<CsvTable> parse_csv(std::string_view text, const std::string& label, std::size_t max_cells = max_csv_cells);
Result<CsvTable> load_csv(const std::string& path);

} // namespace ikebana::assets
