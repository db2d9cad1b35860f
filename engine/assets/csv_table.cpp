#include "engine/assets/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <utility>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/core/utf8.hpp"

namespace ikebana::assets {

namespace {

// A record's cells (RFC 4180): fields separated by commas, optionally quoted ("a, b", "" for a quote,
// and line breaks inside the quotes, as spreadsheets write a cell with Enter in it). It reads one
// record from `at` and leaves `at` after its line ending; `line` counts the file's physical lines,
// so messages name the line where a thing is, not where its record began. At most `keep` cells are
// kept: past them the rest are only counted, so a row of millions of commas costs no memory.
struct Reader {
    std::string_view text;
    std::string label;
    std::size_t at = 0;
    std::size_t line = 1;
    std::size_t line_start = 0; // where the current physical line begins, for columns

    [[nodiscard]] bool done() const { return at >= text.size(); }
    [[nodiscard]] std::size_t column() const { return at - line_start + 1; }
    [[nodiscard]] bool at_line_end() const { return done() || text[at] == '\n' || text[at] == '\r'; }
    std::string where(std::size_t l, std::size_t c) const { return label + ":" + std::to_string(l) + ":" + std::to_string(c) + ": "; }
    // Past one line ending ("\r\n", "\n" or a lone "\r").
    void end_line() {
        if (done()) return;
        at += text.substr(at, 2) == "\r\n" ? 2 : 1;
        ++line;
        line_start = at;
    }
    // A blank or comment line where a record would begin: skipped.
    bool skip_blank_or_comment() {
        std::size_t i = at;
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
        const bool blank = i >= text.size() || text[i] == '\n' || text[i] == '\r';
        if (!blank && text[at] != '#') return false;
        while (!at_line_end()) ++at;
        end_line();
        return true;
    }

    struct Record {
        std::vector<std::string> cells;
        std::vector<std::pair<std::size_t, std::size_t>> starts; // each kept cell's line and column
        std::size_t count = 0;      // every cell, kept or not
        std::size_t first_line = 0; // where it began
        std::size_t last_line = 0;  // where it ended (a quoted line break spans lines)
    };
    Result<Record> record(std::size_t keep) {
        Record r;
        r.first_line = line;
        for (;;) {
            std::string cell;
            const bool kept = r.count < keep;
            if (kept) r.starts.emplace_back(line, column());
            if (!done() && text[at] == '"') {
                const std::size_t open_line = line, open_column = column();
                ++at;
                bool closed = false;
                while (!done()) {
                    const char c = text[at];
                    if (c == '"') {
                        if (at + 1 < text.size() && text[at + 1] == '"') {
                            if (kept) cell += '"';
                            at += 2;
                            continue;
                        }
                        closed = true;
                        ++at;
                        break;
                    }
                    if (c == '\n' || c == '\r') {
                        const std::size_t before = at;
                        end_line();
                        if (kept) cell.append(text.substr(before, at - before));
                        continue;
                    }
                    if (kept) cell += c;
                    ++at;
                }
                if (!closed) return make_error(ErrorCode::parse_error, where(open_line, open_column) + "unterminated quote (its field runs to the end of the file)");
                if (!done() && text[at] != ',' && !at_line_end()) return make_error(ErrorCode::parse_error, where(line, column()) + "expected ',' after a quoted field");
            } else {
                const std::size_t from = at;
                while (!done() && text[at] != ',' && text[at] != '\n' && text[at] != '\r') ++at;
                if (kept) {
                    const std::string_view raw = text.substr(from, at - from);
                    // Surrounding blanks are not part of the value.
                    const auto first = raw.find_first_not_of(" \t");
                    const auto last = raw.find_last_not_of(" \t");
                    if (first != std::string_view::npos) cell = std::string(raw.substr(first, last - first + 1));
                }
            }
            ++r.count;
            if (kept) r.cells.push_back(std::move(cell));
            if (done() || text[at] != ',') break;
            ++at; // the comma
        }
        r.last_line = line;
        end_line();
        return r;
    }
};

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
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    // A file that is not UTF-8 (a spreadsheet's Latin-1 or Windows-1252 export) is read as
    // Windows-1252, and a note says so and where the first such byte is.
    std::string decoded;
    if (const auto bad = first_non_utf8(text)) {
        std::size_t line = 1, line_start = 0;
        for (std::size_t i = 0; i < *bad; ++i) {
            if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) {
                ++line;
                line_start = i + 1;
            }
        }
        table.note = label + ":" + std::to_string(line) + ":" + std::to_string(*bad - line_start + 1) + ": " + byte_text(text, *bad) +
                     " is not UTF-8: the file is read as Windows-1252 (Latin-1), as spreadsheets write it";
        decoded = windows1252_to_utf8(text);
        text = decoded;
    }
    Reader in{text, label};
    bool header_seen = false;
    while (!in.done()) {
        if (in.skip_blank_or_comment()) continue;
        const std::size_t line_no = in.line;
        const std::string where = label + ":" + std::to_string(line_no) + ":";
        // The header may have as many columns as a table may; a row, as many as the header (one more
        // is kept to tell a wide row, the rest only counted).
        auto record = in.record(header_seen ? table.columns.size() + 1 : max_csv_columns + 1);
        if (!record) return std::move(record).error();
        auto& cells = record->cells;
        if (!header_seen) {
            header_seen = true;
            if (record->count > max_csv_columns) {
                return make_error(ErrorCode::parse_error, where + "1: " + std::to_string(record->count) + " columns, more than the " +
                                                              std::to_string(max_csv_columns) + " a table may have here");
            }
            for (std::size_t i = 0; i < cells.size(); ++i) {
                const auto& c = cells[i];
                const std::string at = in.where(record->starts[i].first, record->starts[i].second);
                if (c.empty()) return make_error(ErrorCode::parse_error, at + "empty column name in the header");
                if (table.find(c)) return make_error(ErrorCode::parse_error, at + "column '" + c + "' appears twice");
                table.columns.push_back(CsvColumn{c, {}, std::nullopt});
            }
            table.header_last_line = record->last_line;
            continue;
        }
        if (record->count != table.columns.size()) {
            return make_error(ErrorCode::parse_error, where + "1: expected " + std::to_string(table.columns.size()) + " fields (as the header), found " +
                                                          std::to_string(record->count));
        }
        if (table.rows() == max_csv_rows) {
            return make_error(ErrorCode::parse_error, where + "1: more than " + std::to_string(max_csv_rows) + " rows, the most a table may have here");
        }
        if ((table.rows() + 1) * table.columns.size() > max_cells) {
            return make_error(ErrorCode::parse_error, where + "1: more than " + std::to_string(max_cells) +
                                                          " cells (rows x columns), the most a table may hold here (about " +
                                                          std::to_string(max_cells * 40 >> 20) + " MiB in memory); split the file");
        }
        for (std::size_t c = 0; c < cells.size(); ++c) table.columns[c].text.push_back(std::move(cells[c]));
        table.line_of_row.push_back(line_no);
        table.last_line_of_row.push_back(record->last_line);
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
