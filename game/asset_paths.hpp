#pragma once
#include <filesystem>

#include "engine/core/result.hpp"

namespace ikebana::game {

// The assets folder: $IKEBANA_ASSETS if set, else the source tree's assets/ the build was made from.
[[nodiscard]] std::filesystem::path asset_dir();
// A path from a scene or species file: absolute stays, relative is taken from the assets folder.
[[nodiscard]] std::filesystem::path asset_path(const std::filesystem::path& relative);

// A file named inside another (a species' mesh, a scene's species or trajectory, a lesson's scene, a
// session's lesson): looked for beside the file that names it, then in the assets folder (the shipped
// files name each other from there, and a designer's file may use the shipped meshes), and only there:
// a path that leads outside both (absolute, ../, a link out) is refused as such (invalid_argument),
// whether or not a file is there. Found in neither: not_found, saying where it looked. Without a naming
// file (a path from the command line, a scene made in code), any path, the working directory first.
// Whether `path`, its links and ../ resolved, lies below `folder` (false where either cannot be resolved).
[[nodiscard]] bool below(const std::filesystem::path& folder, const std::filesystem::path& path);
[[nodiscard]] Result<std::filesystem::path> named_from(const std::filesystem::path& naming_file, const std::filesystem::path& named);

} // namespace ikebana::game
