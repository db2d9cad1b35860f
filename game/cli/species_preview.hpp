#pragma once
#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace ikebana::game {

struct PreviewOptions {
    std::string file;
    std::string out = "preview";
    std::string size = "480x640";
    std::uint32_t width = 480, height = 640; // from size
    std::uint32_t turns = 8;
    std::string json;
    bool watch = false;
    std::uint32_t passes = 0; // with watch: previews before it stops (0: until interrupted)
    bool validation = false;
    bool window = false;        // on screen instead of in pictures
    std::uint32_t frames = 0;   // with window: stop after this many frames (0: when closed)
    std::string screenshot;     // with window: the last frame
};

// `ikebana species preview FILE`: a designer's look at a species alone (species_mechanics.hpp's
// trials, pictured offscreen, and a turntable); `--watch` does it again on every save.
void add_species_preview_command(CLI::App& species, int& exit_code);
int run_species_preview(const PreviewOptions& options);

} // namespace ikebana::game
