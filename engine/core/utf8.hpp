#pragma once
// Text as files and people give it: UTF-8 is checked, not assumed. JSON (and every file this program
// writes) is UTF-8; a byte that is not UTF-8 in a name, a cell or a database's text once aborted the
// program when it was written out. Lab files from spreadsheets are often Windows-1252 (a superset of
// Latin-1's printable characters): such a file is read as that, with a note that says so.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace ikebana {

// Where the first byte that does not begin or continue a well-formed UTF-8 character is (an
// overlong form, a surrogate, a value past U+10FFFF, a truncated sequence), or nothing when all is.
[[nodiscard]] std::optional<std::size_t> first_non_utf8(std::string_view text) noexcept;
[[nodiscard]] inline bool is_utf8(std::string_view text) noexcept { return !first_non_utf8(text); }

// The text with each byte that is not UTF-8 replaced by U+FFFD (the replacement character), for text
// that must be shown whatever it holds (a database cell written by another program).
[[nodiscard]] std::string utf8_or_replacement(std::string_view text);

// Each byte read as Windows-1252 (Latin-1 where it defines no character), written as UTF-8.
[[nodiscard]] std::string windows1252_to_utf8(std::string_view text);

// "byte 0xEB" for messages: the byte at `at` that is not UTF-8.
[[nodiscard]] std::string byte_text(std::string_view text, std::size_t at);

// A value named on the command line or typed: an error sentence when it is not UTF-8, e.g.
// "--trainee: not UTF-8 text (byte 0xEB at position 3)", or nothing.
[[nodiscard]] std::optional<std::string> non_utf8_words(std::string_view what, std::string_view text);

// Text from data (a CSV's header or cells, a database's names) made safe to print on a terminal: each
// control character but the line break and the tab (C0, DEL, and C1 as UTF-8 encodes it) is shown as
// `\x1b` rather than sent (an escape sequence in a cell could retitle the window or clear the screen),
// and bytes that are not UTF-8 become U+FFFD.
[[nodiscard]] std::string terminal_text(std::string_view text);

} // namespace ikebana
