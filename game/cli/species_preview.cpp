#include "game/cli/species_preview.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <thread>

#include <nlohmann/json.hpp>

#include "engine/assets/json_checker.hpp"
#include "engine/assets/files.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "game/meshes/procedural_meshes.hpp"
#include "game/app/preview_window.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/option_checks.hpp"
#include "game/world/species_mechanics.hpp"
#include "systems/presentation/draw_list.hpp"

namespace ikebana::game {

namespace {

constexpr double pi = 3.14159265358979323846;
const char* const who = "ikebana species preview: ";

render::OverlayPanel caption(std::vector<std::string> lines) {
    render::OverlayPanel p;
    p.scale = 1.5f;
    p.lines = std::move(lines);
    return p;
}

// The images side by side, on one row (all the same size).
render::RgbaImage sheet_of(const std::vector<render::RgbaImage>& images) {
    render::RgbaImage sheet;
    if (images.empty()) return sheet;
    sheet.width = images.front().width * static_cast<std::uint32_t>(images.size());
    sheet.height = images.front().height;
    sheet.pixels.assign(static_cast<std::size_t>(sheet.width) * sheet.height * 4, 0);
    for (std::size_t k = 0; k < images.size(); ++k) {
        const auto& im = images[k];
        if (im.width != images.front().width || im.height != sheet.height) continue;
        for (std::uint32_t y = 0; y < im.height; ++y) {
            std::copy_n(im.pixels.begin() + static_cast<std::ptrdiff_t>(y) * im.width * 4, im.width * 4,
                        sheet.pixels.begin() + (static_cast<std::ptrdiff_t>(y) * sheet.width + k * im.width) * 4);
        }
    }
    return sheet;
}

// What a trial showed, a short line each (a picture's caption; joined, a line of the summary).
std::vector<std::string> stand_lines(const StandTrial& t) {
    char set[64], now[64], hold[96];
    std::snprintf(set, sizeof set, "set at %.0f deg: %s", t.set_at_deg, t.stands ? "stands" : "FALLS");
    std::snprintf(now, sizeof now, "now %.0f deg from vertical", t.tilt_deg);
    // Upright, its weight pulls straight down the pins: nothing for them to hold against.
    if (t.gravity_nm > 1e-6) std::snprintf(hold, sizeof hold, "the pins hold %.1fx its pull", t.margin());
    else std::snprintf(hold, sizeof hold, "its weight does not pull it over");
    if (t.stands) return {set, now, hold};
    return {set, t.reason, now};
}

std::vector<std::string> sag_lines(const SagTrial& s) {
    char top[96], angle[64];
    std::snprintf(top, sizeof top, "its top %.0f mm %s the base", std::abs(s.tip_drop_mm), s.tip_drop_mm >= 0.0 ? "below" : "above");
    std::snprintf(angle, sizeof angle, "%.0f deg %s level", std::abs(s.tip_angle_deg), s.tip_angle_deg >= 0.0 ? "below" : "above");
    return {"held level by its base", top, angle};
}

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const auto& l : lines) out += (out.empty() ? "" : ", ") + l;
    return out;
}

std::vector<std::string> titled(const std::string& title, std::vector<std::string> lines) {
    lines.insert(lines.begin(), title);
    return lines;
}

nlohmann::json mechanics_json(const SpeciesMechanics& m) {
    nlohmann::json stands = nlohmann::json::array();
    for (const auto& t : m.stands) {
        stands.push_back({{"set_at_deg", t.set_at_deg}, {"stands", t.stands}, {"reason", t.reason}, {"tilt_deg", t.tilt_deg},
                          {"holding_nm", t.holding_nm}, {"gravity_nm", t.gravity_nm},
                          {"margin", t.gravity_nm > 1e-6 ? nlohmann::json(t.margin()) : nlohmann::json(nullptr)}});
    }
    return {{"species", m.id}, {"length_mm", m.length_mm}, {"settle_s", mechanics_settle_s}, {"stands", stands},
            {"sag", {{"tip_drop_mm", m.sag.tip_drop_mm}, {"tip_angle_deg", m.sag.tip_angle_deg}}}};
}

// The numbers: words on standard output (standard error when the JSON goes there), the JSON as asked.
int print_numbers(const PreviewOptions& o, const SpeciesMechanics& m) {
    FILE* words = o.json == "-" ? stderr : stdout;
    std::fprintf(words, "%s (%s, %.0f mm), after %.0f s in each trial:\n", m.id.c_str(), o.file.c_str(), m.length_mm, mechanics_settle_s);
    for (const auto& t : m.stands) std::fprintf(words, "  %s\n", joined(stand_lines(t)).c_str());
    std::fprintf(words, "  %s\n", joined(sag_lines(m.sag)).c_str());
    if (!o.json.empty()) {
        const std::string text = assets::json_text(mechanics_json(m), 2) + "\n";
        if (o.json == "-") std::fputs(text.c_str(), stdout);
        else if (auto wr = assets::write_text_file(o.json, text); !wr) {
            std::cerr << who << "--json: " << wr.error().message << "\n";
            return 1;
        }
    }
    std::fflush(stdout);
    return 0;
}

// What the window shows: the turntable, each trial, their captions.
std::vector<PreviewView> views_of(const SpeciesMechanics& m) {
    char title[96];
    std::snprintf(title, sizeof title, "%s, %.0f mm", m.id.c_str(), m.length_mm);
    std::vector<PreviewView> views;
    views.push_back({"1", "turning", m.scenes.front().last, {title}, true});
    for (std::size_t i = 0; i < m.stands.size() && i < m.scenes.size(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "at %.0f", m.stands[i].set_at_deg);
        views.push_back({std::to_string(views.size() + 1), name, m.scenes[i].last, titled(title, stand_lines(m.stands[i])), false});
    }
    views.push_back({std::to_string(views.size() + 1), "level", m.scenes.back().last, titled(title, sag_lines(m.sag)), false});
    return views;
}

// One preview: the trials, their pictures and the turntable into `out`, the numbers on stdout.
int preview_once(const PreviewOptions& o, render::StereoRenderer& renderer) {
    auto m = species_mechanics(o.file);
    if (!m) {
        std::cerr << who << m.error().message << "\n";
        return 2;
    }
    const double aspect = static_cast<double>(o.width) / static_cast<double>(o.height);
    const std::filesystem::path out(o.out);
    std::vector<render::RgbaImage> sheet;
    const auto draw = [&](const components::FrameSnapshot& frame, const render::StereoRig& rig, std::vector<std::string> lines,
                          const std::string& name) -> Result<render::RgbaImage> {
        renderer.set_overlay({caption(std::move(lines))});
        auto image = renderer.render(systems::build_draw_list(frame), rig, false);
        if (!image) return std::move(image).error();
        if (auto wr = render::write_png(out / name, image->composed); !wr) return std::move(wr).error();
        return std::move(image->composed);
    };
    // The turntable: the upright trial's flower, turned about itself.
    const auto& upright = m->scenes.front().last;
    for (std::uint32_t k = 0; k < o.turns; ++k) {
        const double yaw = 2.0 * pi * k / o.turns;
        char name[64], line[96];
        std::snprintf(name, sizeof name, "turntable_%02u.png", k);
        std::snprintf(line, sizeof line, "%s, %.0f mm: turned %.0f deg", m->id.c_str(), m->length_mm, yaw * 180.0 / pi);
        auto image = draw(upright, preview_framing(upright, aspect, yaw), {line}, name);
        if (!image) {
            std::cerr << who << image.error().message << "\n";
            return 3;
        }
        if (k == 0) sheet.push_back(std::move(image).value());
    }
    for (std::size_t i = 0; i < m->stands.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "stand_%02.0f.png", m->stands[i].set_at_deg);
        auto image = draw(m->scenes[i].last, preview_framing(m->scenes[i].last, aspect, 0.0), titled(m->id, stand_lines(m->stands[i])), name);
        if (!image) {
            std::cerr << who << image.error().message << "\n";
            return 3;
        }
        sheet.push_back(std::move(image).value());
    }
    auto sag = draw(m->scenes.back().last, preview_framing(m->scenes.back().last, aspect, 0.0), titled(m->id, sag_lines(m->sag)), "sag.png");
    if (!sag) {
        std::cerr << who << sag.error().message << "\n";
        return 3;
    }
    sheet.push_back(std::move(sag).value());
    if (auto wr = render::write_png(out / "sheet.png", sheet_of(sheet)); !wr) {
        std::cerr << who << wr.error().message << "\n";
        return 1;
    }
    if (const int code = print_numbers(o, *m); code != 0) return code;
    std::fprintf(o.json == "-" ? stderr : stdout, "pictures in %s: sheet.png (the flower, each trial), turntable_00..%02u.png, stand_00/45/70.png, sag.png\n",
                 o.out.c_str(), o.turns - 1);
    std::fflush(stdout);
    return 0;
}

} // namespace

int run_species_preview(const PreviewOptions& o) {
    if (o.watch && o.json == "-") {
        std::cerr << who << "--watch writes a JSON document each preview; with --json - they would run together: give --json a file\n";
        return 2;
    }
    if (!o.json.empty() && o.json != "-") {
        if (auto ok = assets::check_output_path(o.json); !ok) {
            std::cerr << who << "--json: " << ok.error().message << "\n";
            return 2;
        }
    }
    if (o.window) {
        // On screen instead of in pictures: the numbers once (and after each save), the window until closed.
        PreviewWindowOptions w{o.file, o.width, o.height, o.watch, o.passes, o.frames, o.screenshot, o.validation};
        return run_preview_window(w, [&o]() -> Result<std::vector<PreviewView>> {
            auto m = species_mechanics(o.file);
            if (!m) return std::move(m).error();
            (void)print_numbers(o, *m);
            return views_of(*m);
        });
    }
    if (auto folder = assets::create_output_folder(o.out); !folder) {
        std::cerr << who << "--out: " << folder.error().message << "\n";
        return 2;
    }
    auto ctx = render::VulkanContext::create({.validation = o.validation, .require_validation = false, .instance_extensions = {}});
    if (!ctx) {
        std::cerr << who << ctx.error().message << "\n";
        return 3;
    }
    render::RendererOptions ro;
    ro.eye_width = o.width;
    ro.eye_height = o.height;
    ro.mode = render::StereoMode::mono;
    ro.asset_dir = asset_dir();
    ro.generated_mesh = part_mesh_of_name; // a petal or leaf a species draws without a file
    auto renderer = render::StereoRenderer::create(**ctx, ro);
    if (!renderer) {
        std::cerr << who << renderer.error().message << "\n";
        return 3;
    }
    auto seen = assets::last_changed(o.file);
    int code = preview_once(o, **renderer);
    if (!o.watch) return code;
    // Again each time the file is saved, until interrupted (or `passes` previews, for scripts and tests).
    std::printf("watching %s: each save previews it again (Ctrl+C ends)\n", o.file.c_str());
    std::fflush(stdout);
    for (std::uint32_t passes = 1; o.passes == 0 || passes < o.passes;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
        const auto now = assets::last_changed(o.file);
        if (now == seen) continue;
        seen = now;
        // A save is often a truncate and a write: let it finish.
        std::this_thread::sleep_for(std::chrono::milliseconds(150));
        seen = assets::last_changed(o.file);
        std::printf("\n%s changed:\n", o.file.c_str());
        code = preview_once(o, **renderer);
        ++passes;
    }
    return code;
}

void add_species_preview_command(CLI::App& species, int& exit_code) {
    auto o = std::make_shared<PreviewOptions>();
    auto* cmd = species.add_subcommand("preview",
                                       "A species alone: a turntable framed on its whole height, and whether it stands in the kenzan at 0, 45 and 70 "
                                       "degrees and how far it sags held level by its base, as numbers and pictures (PNGs)");
    cmd->add_option("file", o->file, "Species file")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", o->out, "Folder for the pictures")->capture_default_str();
    cmd->add_option("--size", o->size, "One picture's size, WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--turns", o->turns, "Pictures in the turntable")->capture_default_str()->check(CLI::Range(1u, 72u));
    cmd->add_option("--json", o->json, "The numbers as JSON into this file (- for standard output)");
    cmd->add_flag("--watch", o->watch, "Preview again each time the file is saved");
    cmd->add_option("--passes", o->passes, "With --watch: stop after this many previews (0: never)")->capture_default_str();
    cmd->add_flag("--window", o->window, "Show it in a window instead of writing pictures: the turntable (drag to turn), keys 1-5 for the trials");
    cmd->add_option("--frames", o->frames, "With --window: stop after this many frames (0: when closed)")->capture_default_str();
    cmd->add_option("--screenshot", o->screenshot, "With --window: the last frame as a PNG");
    cmd->add_flag("--validation", o->validation, "Run with the Vulkan validation layer");
    cmd->callback([o, &exit_code] {
        unsigned w = 0, h = 0;
        char x = 0, extra = 0;
        if (std::sscanf(o->size.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 16 || h < 16 || w > 4096 || h > 4096) {
            std::cerr << who << "--size '" << o->size << "': expected WIDTHxHEIGHT, each 16-4096 pixels (e.g. 480x640)\n";
            exit_code = 2;
            return;
        }
        o->width = w;
        o->height = h;
        exit_code = run_species_preview(*o);
    });
}

} // namespace ikebana::game
