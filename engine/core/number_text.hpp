#pragma once
// A number as a person typed it, for messages: "0.5", "1e+200", "inf" (the stream's shortest form at
// six significant digits). One definition for every message that quotes a value back.
#include <sstream>
#include <string>

namespace ikebana {

[[nodiscard]] inline std::string number_text(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

} // namespace ikebana
