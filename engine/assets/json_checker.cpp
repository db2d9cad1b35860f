#include "engine/assets/json_checker.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ikebana::assets {

namespace {
std::string join(const std::string& path, const char* key) { return path + "/" + key; }

std::string range_text(NumberRange r) {
    const bool has_min = std::isfinite(r.min);
    const bool has_max = std::isfinite(r.max);
    auto fmt = [](double v) {
        std::ostringstream s;
        s << v;
        return s.str();
    };
    if (has_min && has_max) return std::string(r.min_exclusive ? "in (" : "in [") + fmt(r.min) + ", " + fmt(r.max) + "]";
    if (has_min) return std::string(r.min_exclusive ? "> " : ">= ") + fmt(r.min);
    if (has_max) return "<= " + fmt(r.max);
    return "";
}
} // namespace

std::string JsonChecker::describe(const Json& value) {
    switch (value.type()) {
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return "an array";
    case Json::value_t::null: return "null";
    case Json::value_t::discarded: return "nothing";
    default: {
        auto text = value.dump();
        if (text.size() > 40) text = text.substr(0, 37) + "...";
        return text;
    }
    }
}

void JsonChecker::problem(const std::string& path, const std::string& what) {
    problems_.push_back(file_ + ": " + (path.empty() ? std::string("/") : path) + ": " + what);
}

Error JsonChecker::error() const {
    std::string message;
    for (const auto& p : problems_) {
        if (!message.empty()) message += "\n";
        message += p;
    }
    return make_error(ErrorCode::parse_error, message);
}

std::optional<TextPosition> json_nesting_beyond(std::string_view text, std::size_t max_depth) {
    TextPosition at;
    std::size_t depth = 0;
    bool in_string = false;
    bool escaped = false;
    for (const char c : text) {
        if (in_string) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth) return at;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
        if (c == '\n') {
            ++at.line;
            at.column = 1;
        } else {
            ++at.column;
        }
    }
    return std::nullopt;
}

std::string without_echo(std::string message) {
    // nlohmann's "last read: '...'" quotes the file; the line and column already say where.
    for (auto at = message.find("last read: '"); at != std::string::npos; at = message.find("last read: '")) {
        const auto close = message.find("'; ", at + 12);
        const auto end = close == std::string::npos ? message.size() : close + 3;
        message.erase(at, end - at);
    }
    while (!message.empty() && (message.back() == ' ' || message.back() == ';')) message.pop_back();
    return message;
}

namespace {
// "LINE:COLUMN" of the byte at `offset`, which an editor can jump to.
std::string line_column(std::string_view text, std::size_t offset) {
    std::size_t line = 1;
    std::size_t column = 1;
    for (std::size_t i = 0; i < std::min(offset, text.size()); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return std::to_string(line) + ":" + std::to_string(column);
}
} // namespace

std::optional<Json> JsonChecker::parse(std::string_view text) {
    // A NUL byte ends the parser's input early ("unexpected end of input" said nothing of it).
    if (const auto nul = text.find('\0'); nul != std::string_view::npos) {
        problems_.push_back(file_ + ":" + line_column(text, nul) + ": a NUL byte (0x00): not JSON text");
        return std::nullopt;
    }
    if (const auto deep = json_nesting_beyond(text, max_json_depth)) {
        problems_.push_back(file_ + ":" + std::to_string(deep->line) + ":" + std::to_string(deep->column) +
                            ": arrays and objects nest deeper than " + std::to_string(max_json_depth) + " levels");
        return std::nullopt;
    }
    try {
        return Json::parse(text.begin(), text.end());
    } catch (const Json::parse_error& e) {
        std::string what = without_echo(e.what());
        if (const auto at = what.find("syntax error"); at != std::string::npos) what = what.substr(at);
        problems_.push_back(file_ + ":" + line_column(text, e.byte > 0 ? e.byte - 1 : 0) + ": not valid JSON: " + what);
        return std::nullopt;
    } catch (const Json::out_of_range& e) {
        // A number too large for a double ("1e400"): nlohmann names the number but not where it is.
        std::string what = e.what();
        if (const auto at = what.find("number overflow"); at != std::string::npos) what = what.substr(at);
        problems_.push_back(file_ + ": not valid JSON: " + what);
        return std::nullopt;
    } catch (const Json::exception& e) {
        problems_.push_back(file_ + ": not valid JSON: " + without_echo(e.what()));
        return std::nullopt;
    }
}

std::optional<Json> JsonChecker::parse_object(std::string_view text) {
    auto root = parse(text);
    if (root && !root->is_object()) {
        problem("", "expected an object at the top, got " + describe(*root));
        return std::nullopt;
    }
    return root;
}

std::optional<double> JsonChecker::number(const Json& object, const std::string& path, const char* key,
                                          NumberRange range, bool required) {
    const auto it = object.find(key);
    if (it == object.end()) {
        if (required) problem(join(path, key), "missing; expected a number " + range_text(range));
        return std::nullopt;
    }
    if (!it->is_number()) {
        problem(join(path, key), "expected a number " + range_text(range) + ", got " + describe(*it));
        return std::nullopt;
    }
    const double v = it->get<double>();
    const bool below = range.min_exclusive ? !(v > range.min) : !(v >= range.min);
    if (!std::isfinite(v) || below || v > range.max) {
        problem(join(path, key), "expected a number " + range_text(range) + ", got " + describe(*it));
        return std::nullopt;
    }
    return v;
}

std::optional<std::int64_t> JsonChecker::integer(const Json& object, const std::string& path, const char* key,
                                                 std::int64_t min, std::int64_t max, bool required) {
    const auto it = object.find(key);
    const std::string expected = "expected an integer >= " + std::to_string(min) +
                                 (max < std::numeric_limits<std::int64_t>::max() ? " and <= " + std::to_string(max) : "");
    if (it == object.end()) {
        if (required) problem(join(path, key), "missing; " + expected);
        return std::nullopt;
    }
    if (!it->is_number_integer() && !(it->is_number_float() && std::floor(it->get<double>()) == it->get<double>() &&
                                      std::abs(it->get<double>()) < 9e15)) {
        problem(join(path, key), expected + ", got " + describe(*it));
        return std::nullopt;
    }
    const auto v = it->is_number_unsigned() && it->get<std::uint64_t>() > static_cast<std::uint64_t>(max)
                       ? max + 1
                       : (it->is_number_float() ? static_cast<std::int64_t>(it->get<double>()) : it->get<std::int64_t>());
    if (v < min || v > max) {
        problem(join(path, key), expected + ", got " + describe(*it));
        return std::nullopt;
    }
    return v;
}

std::optional<std::string> JsonChecker::string(const Json& object, const std::string& path, const char* key,
                                               bool required) {
    const auto it = object.find(key);
    if (it == object.end()) {
        if (required) problem(join(path, key), "missing; expected a string");
        return std::nullopt;
    }
    if (!it->is_string()) {
        problem(join(path, key), "expected a string, got " + describe(*it));
        return std::nullopt;
    }
    return it->get<std::string>();
}

std::optional<std::string> JsonChecker::choice(const Json& object, const std::string& path, const char* key,
                                               const std::vector<std::string>& allowed, bool required) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
    const auto it = object.find(key);
    if (it == object.end()) {
        if (required) problem(join(path, key), "missing; expected one of " + list);
        return std::nullopt;
    }
    if (it->is_string()) {
        const auto v = it->get<std::string>();
        for (const auto& a : allowed) {
            if (a == v) return v;
        }
    }
    problem(join(path, key), "expected one of " + list + ", got " + describe(*it));
    return std::nullopt;
}

std::optional<bool> JsonChecker::boolean(const Json& object, const std::string& path, const char* key, bool required) {
    const auto it = object.find(key);
    if (it == object.end()) {
        if (required) problem(join(path, key), "missing; expected true or false");
        return std::nullopt;
    }
    if (!it->is_boolean()) {
        problem(join(path, key), "expected true or false, got " + describe(*it));
        return std::nullopt;
    }
    return it->get<bool>();
}

const Json* JsonChecker::object(const Json& parent, const std::string& path, const char* key, bool required) {
    const auto it = parent.find(key);
    if (it == parent.end()) {
        if (required) problem(join(path, key), "missing; expected an object");
        return nullptr;
    }
    if (!it->is_object()) {
        problem(join(path, key), "expected an object, got " + describe(*it));
        return nullptr;
    }
    return &*it;
}

const Json* JsonChecker::array(const Json& parent, const std::string& path, const char* key, bool required) {
    const auto it = parent.find(key);
    if (it == parent.end()) {
        if (required) problem(join(path, key), "missing; expected an array");
        return nullptr;
    }
    if (!it->is_array()) {
        problem(join(path, key), "expected an array, got " + describe(*it));
        return nullptr;
    }
    return &*it;
}

std::optional<std::vector<double>> JsonChecker::numbers(const Json& parent, const std::string& path, const char* key,
                                                        NumberRange range, std::size_t min_count, bool required) {
    const Json* list = array(parent, path, key, required);
    if (!list) return std::nullopt;
    const std::string here = join(path, key);
    if (list->size() < min_count) {
        problem(here, "expected at least " + std::to_string(min_count) + " numbers, got " + std::to_string(list->size()));
        return std::nullopt;
    }
    std::vector<double> out;
    bool good = true;
    for (std::size_t i = 0; i < list->size(); ++i) {
        const Json& v = (*list)[i];
        const bool below = v.is_number() && (range.min_exclusive ? !(v.get<double>() > range.min) : !(v.get<double>() >= range.min));
        if (!v.is_number() || below || v.get<double>() > range.max || !std::isfinite(v.get<double>())) {
            problem(here + "/" + std::to_string(i), "expected a number " + range_text(range) + ", got " + describe(v));
            good = false;
            continue;
        }
        out.push_back(v.get<double>());
    }
    if (!good) return std::nullopt;
    return out;
}

void JsonChecker::no_unknown_keys(const Json& object, const std::string& path, const std::vector<std::string>& known) {
    if (!object.is_object()) return;
    for (const auto& [key, value] : object.items()) {
        bool found = false;
        for (const auto& k : known) found = found || k == key;
        if (!found) {
            std::string list;
            for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
            problem(path + "/" + key, "unknown field (known here: " + list + ")");
        }
    }
}

} // namespace ikebana::assets
