#include "game/cli/render_command.hpp"

#include <memory>

#include "game/asset_paths.hpp"
#include "game/cli/option_checks.hpp"

namespace ikebana::game {

void add_render_command(CLI::App& app, int& exit_code) {
    auto o = std::make_shared<RenderOptions>();
    o->scene = (asset_dir() / "scenes" / "default.json").string();
    auto* cmd = app.add_subcommand("render", "Render a scene offscreen (no window or display needed) to PNGs of each eye and the composed frame");
    auto* scene = cmd->add_option("--scene", o->scene, "Scene file")->capture_default_str();
    cmd->add_option("--lesson", o->lesson, "A lesson (id or file) instead of a scene: its table as a trainee first sees it")->excludes(scene);
    cmd->add_option("--frames", o->frames, "Frames to render, one per render period")->capture_default_str()->check(CLI::Range(1u, 100000u));
    cmd->add_option("--stereo", o->stereo, "sbs, rows (polarized displays), anaglyph or mono (default: the scene's display)");
    cmd->add_option("--out", o->out, "Folder for the PNGs")->required();
    cmd->add_option("--width", o->width, "Width of one eye's image")->capture_default_str()->check(CLI::Range(16u, 8192u));
    cmd->add_option("--height", o->height, "Height of one eye's image")->capture_default_str()->check(CLI::Range(16u, 8192u));
    cmd->add_option("--yaw", o->yaw_deg, "Orbit the camera about the arrangement, degrees")->capture_default_str()->check(finite_in(-360.0, 360.0, "degrees"));
    cmd->add_option("--pitch", o->pitch_deg, "Raise the camera, degrees")->capture_default_str()->check(finite_in(-89.0, 89.0, "degrees"));
    cmd->add_option("--msaa", o->msaa, "Anti-aliasing: samples a pixel (1 none, 2, 4, 8; the device's nearest at or below)")
        ->capture_default_str()
        ->check(CLI::IsMember({1u, 2u, 4u, 8u}));
    cmd->add_flag("--full-detail", o->full_detail, "Draw every mesh as modelled, even a petal a few pixels long (by default those get a coarse copy)");
    cmd->add_flag("--validation", o->validation, "Run with the Vulkan validation layer; any error fails the command");
    cmd->callback([o, &exit_code] { exit_code = run_render(*o); });
}

} // namespace ikebana::game
