#pragma once
// Reading designer-written JSON without trusting it. Every accessor records a problem instead of
// throwing, so one pass reports everything wrong with a file, each as
//   sunflower.json: /stem/segments: expected an integer >= 2, got "ten"
// and the caller applies nothing unless the list is empty.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/result.hpp"

namespace ikebana::assets {

using Json = nlohmann::json;

// JSON written out. Every string in it should already be UTF-8 (names, cells and settings are checked
// where they come in), but a byte that is not would make the library throw halfway through a file
// (a trainee's name once aborted `history --json` for good): here it becomes U+FFFD instead.
template <typename J>
[[nodiscard]] std::string json_text(const J& j, int indent = -1) {
    return j.dump(indent, ' ', false, J::error_handler_t::replace);
}

struct NumberRange {
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    bool min_exclusive = false;
};

class JsonChecker {
public:
    explicit JsonChecker(std::string file_label) : file_(std::move(file_label)) {}

    // Parses text; a syntax error is recorded with its line and column, and so is anything else the
    // parser refuses (a number too large for a double, a nesting deeper than max_json_depth): every
    // reader of JSON goes through this one door, so none can be crashed by what the parser throws.
    std::optional<Json> parse(std::string_view text);
    // The same, for files whose top is an object (every format of ours): anything else is a problem.
    std::optional<Json> parse_object(std::string_view text);

    // Field accessors. `path` is the JSON pointer of `object`; missing optional fields give nullopt
    // without a problem, missing required ones record one.
    std::optional<double> number(const Json& object, const std::string& path, const char* key, NumberRange range,
                                 bool required = true);
    std::optional<std::int64_t> integer(const Json& object, const std::string& path, const char* key,
                                        std::int64_t min, std::int64_t max, bool required = true);
    std::optional<std::string> string(const Json& object, const std::string& path, const char* key,
                                      bool required = true);
    // One of `allowed`; the problem lists them.
    std::optional<std::string> choice(const Json& object, const std::string& path, const char* key,
                                      const std::vector<std::string>& allowed, bool required = true);
    std::optional<bool> boolean(const Json& object, const std::string& path, const char* key, bool required = true);
    const Json* object(const Json& parent, const std::string& path, const char* key, bool required = true);
    const Json* array(const Json& parent, const std::string& path, const char* key, bool required = true);
    std::optional<std::vector<double>> numbers(const Json& parent, const std::string& path, const char* key,
                                               NumberRange range, std::size_t min_count, bool required = true);
    // Fields not in `known` are reported: a misspelt key must not silently fall back to a default.
    void no_unknown_keys(const Json& object, const std::string& path, const std::vector<std::string>& known);

    void problem(const std::string& path, const std::string& what);
    [[nodiscard]] bool ok() const noexcept { return problems_.empty(); }
    [[nodiscard]] const std::vector<std::string>& problems() const noexcept { return problems_; }
    [[nodiscard]] const std::string& file() const noexcept { return file_; }
    // All problems as one error (code parse_error), one per line.
    [[nodiscard]] Error error() const;

    static std::string describe(const Json& value); // `"ten"`, `12.5`, `an object`, ...

private:
    std::string file_;
    std::vector<std::string> problems_;
};

// Limits a user's file must keep; each refusal names the file and the limit.
inline constexpr std::size_t max_json_depth = 64;                  // our formats nest 5 deep at most

// A parser's message without the text it quotes from the file ("last read: '...'"): errors say where,
// never what a file holds (it may be one the user should not see through us).
[[nodiscard]] std::string without_echo(std::string message);

// Where `text` nests arrays and objects deeper than `max_depth` (outside strings): the 1-based line
// and column of the bracket that goes too deep, or nullopt. A linear scan with no recursion, for
// parsers that recurse (tinygltf) as well as ours.
struct TextPosition {
    std::size_t line = 1;
    std::size_t column = 1;
};
[[nodiscard]] std::optional<TextPosition> json_nesting_beyond(std::string_view text, std::size_t max_depth);


} // namespace ikebana::assets
