#include "engine/assets/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

namespace ikebana::assets {

namespace {

struct Cell {
    std::string text;
    std::size_t column; // 1-based character column where the cell starts
};

// Splits one line into cells; an unterminated quote is an error.
Result<std::vector<Cell>> split(std::string_view line, const std::string& where_prefix) {
    std::vector<Cell> cells;
    std::size_t i = 0;
    for (;;) {
        Cell cell{std::string{}, i + 1};
        if (i < line.size() && line[i] == '"') {
            ++i;
            bool closed = false;
            while (i < line.size()) {
                if (line[i] == '"') {
                    if (i + 1 < line.size() && line[i + 1] == '"') {
                        cell.text += '"';
                        i += 2;
                        continue;
                    }
                    closed = true;
                    ++i;
                    break;
                }
                cell.text += line[i++];
            }
            if (!closed) return make_error(ErrorCode::parse_error, where_prefix + std::to_string(cell.column) + ": unterminated quote");
            if (i < line.size() && line[i] != ',') {
                return make_error(ErrorCode::parse_error, where_prefix + std::to_string(i + 1) + ": expected ',' after a quoted field");
            }
        } else {
            const std::size_t comma = line.find(',', i);
            const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
            cell.text = std::string(line.substr(i, end - i));
            // Surrounding blanks are not part of the value.
            const auto first = cell.text.find_first_not_of(" \t");
            const auto last = cell.text.find_last_not_of(" \t");
            cell.text = first == std::string::npos ? std::string{} : cell.text.substr(first, last - first + 1);
            i = end;
        }
        cells.push_back(std::move(cell));
        if (i >= line.size()) break;
        ++i; // the comma
        if (i == line.size()) {
            cells.push_back(Cell{std::string{}, i + 1});
            break;
        }
    }
    return cells;
}

std::optional<double> number(const std::string& text) {
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc{} || ptr != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

} // namespace

const CsvColumn* CsvTable::find(std::string_view name) const noexcept {
    for (const auto& c : columns) {
        if (c.name == name) return &c;
    }
    return nullptr;
}

std::vector<TextLine> split_lines(std::string_view text) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    std::vector<TextLine> lines;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t end = text.find_first_of("\r\n", start);
        if (end == std::string_view::npos) {
            lines.push_back({text.substr(start), {}});
            break;
        }
        const std::size_t ending = text.substr(end, 2) == "\r\n" ? 2 : 1;
        lines.push_back({text.substr(start, end - start), text.substr(end, ending)});
        start = end + ending;
    }
    return lines;
}

Result<CsvTable> parse_csv(std::string_view text, const std::string& label, std::size_t max_cells) {
    CsvTable table;
    table.label = label;
    bool header_seen = false;
    std::size_t line_no = 0;
    for (const auto& [line, ending] : split_lines(text)) {
        ++line_no;
        if (line.find_first_not_of(" \t") == std::string_view::npos || line.front() == '#') continue;
        const std::string where = label + ":" + std::to_string(line_no) + ":";
        auto cells = split(line, where);
        if (!cells) return std::move(cells).error();
        if (!header_seen) {
            header_seen = true;
            if (cells->size() > max_csv_columns) {
                return make_error(ErrorCode::parse_error, where + "1: " + std::to_string(cells->size()) + " columns, more than the " +
                                                              std::to_string(max_csv_columns) + " a table may have here");
            }
            for (const auto& c : *cells) {
                if (c.text.empty()) return make_error(ErrorCode::parse_error, where + std::to_string(c.column) + ": empty column name in the header");
                if (table.find(c.text)) {
                    return make_error(ErrorCode::parse_error, where + std::to_string(c.column) + ": column '" + c.text + "' appears twice");
                }
                table.columns.push_back(CsvColumn{c.text, {}, std::nullopt});
            }
            continue;
        }
        if (cells->size() != table.columns.size()) {
            return make_error(ErrorCode::parse_error, where + "1: expected " + std::to_string(table.columns.size()) + " fields (as the header), found " +
                                                          std::to_string(cells->size()));
        }
        if (table.rows() == max_csv_rows) {
            return make_error(ErrorCode::parse_error, where + "1: more than " + std::to_string(max_csv_rows) + " rows, the most a table may have here");
        }
        if ((table.rows() + 1) * table.columns.size() > max_cells) {
            return make_error(ErrorCode::parse_error, where + "1: more than " + std::to_string(max_cells) +
                                                          " cells (rows x columns), the most a table may hold here (about " +
                                                          std::to_string(max_cells * 40 >> 20) + " MiB in memory); split the file");
        }
        for (std::size_t c = 0; c < cells->size(); ++c) table.columns[c].text.push_back(std::move((*cells)[c].text));
        table.line_of_row.push_back(line_no);
    }
    if (!header_seen) return make_error(ErrorCode::parse_error, label + ": empty; expected a header row");
    for (auto& column : table.columns) {
        std::vector<double> values;
        bool numeric = true;
        bool any = false;
        for (const auto& cell : column.text) {
            if (cell.empty()) {
                values.push_back(std::numeric_limits<double>::quiet_NaN());
                continue;
            }
            const auto v = number(cell);
            if (!v) {
                numeric = false;
                break;
            }
            any = true;
            values.push_back(*v);
        }
        if (numeric && any) column.numbers = std::move(values);
    }
    return table;
}

Result<CsvTable> load_csv(const std::string& path) {
    auto text = read_text_file(path);
    if (!text) return std::move(text).error();
    return parse_csv(*text, path);
}

} // namespace ikebana::assets
