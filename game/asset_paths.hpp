#pragma once
#include <filesystem>

#include "engine/core/result.hpp"

namespace ikebana::game {

// The assets folder: $IKEBANA_ASSETS if set, else the source tree's assets/ the build was made from.
[[nodiscard]] std::filesystem::path asset_dir();
// A path from a scene or species file: absolute stays, relative is taken from the assets folder.
[[nodiscard]] std::filesystem::path asset_path(const std::filesystem::path& relative);

// A file named inside another (a species' mesh, a scene's species or trajectory, a lesson's scene): an
// absolute path stays; a relative one is looked for beside the file that names it, then in the assets
// folder (the shipped files name each other from there, and a designer's file may use the shipped
// meshes). Found in neither: an error that says where it looked. Without a naming file (a path from
// the command line, a scene made in code), the working directory comes first instead.
[[nodiscard]] Result<std::filesystem::path> named_from(const std::filesystem::path& naming_file, const std::filesystem::path& named);

} // namespace ikebana::game
