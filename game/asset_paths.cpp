#include "game/asset_paths.hpp"

#include <cstdlib>

namespace ikebana::game {

std::filesystem::path asset_dir() {
    if (const char* env = std::getenv("IKEBANA_ASSETS"); env && *env) return env;
    return IKEBANA_ASSET_DIR;
}

std::filesystem::path asset_path(const std::filesystem::path& relative) {
    return relative.is_absolute() ? relative : asset_dir() / relative;
}

} // namespace ikebana::game
