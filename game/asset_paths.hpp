#pragma once
#include <filesystem>

namespace ikebana::game {

// The assets folder: $IKEBANA_ASSETS if set, else the source tree's assets/ the build was made from.
[[nodiscard]] std::filesystem::path asset_dir();
// A path from a scene or species file: absolute stays, relative is taken from the assets folder.
[[nodiscard]] std::filesystem::path asset_path(const std::filesystem::path& relative);

} // namespace ikebana::game
