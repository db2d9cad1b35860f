#pragma once
// The tips and lines the form scoring writes: printf's formats, into a string. Internal to
// game/training/.
#include <cstdio>
#include <string>

namespace ikebana::game::training {

std::string fmt(const char* f, auto... args) {
    char text[400];
    std::snprintf(text, sizeof text, f, args...);
    return text;
}

} // namespace ikebana::game::training
