#include "game/cli/assets_command.hpp"

#include <cstdio>
#include <iostream>

#include "game/asset_paths.hpp"
#include "game/meshes/procedural_meshes.hpp"

namespace ikebana::game {

void add_assets_command(CLI::App& app, int& exit_code) {
    auto* assets_cmd = app.add_subcommand("assets", "Generate the project's own assets");
    assets_cmd->require_subcommand(1);
    auto out = std::make_shared<std::string>(asset_dir().string());
    auto* meshes = assets_cmd->add_subcommand("meshes", "Write the petal, leaf, head and hand glTF meshes");
    meshes->add_option("--out", *out, "Assets folder to write meshes/ into")->capture_default_str();
    meshes->callback([out, &exit_code] {
        const auto written = write_procedural_meshes(*out);
        if (!written) {
            std::cerr << "ikebana assets meshes: " << written.error().message << "\n";
            exit_code = 1;
            return;
        }
        for (const auto& path : *written) std::printf("wrote %s\n", path.string().c_str());
    });
}

} // namespace ikebana::game
