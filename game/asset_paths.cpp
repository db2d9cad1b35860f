#include "game/asset_paths.hpp"

#include <cstdlib>
#include <system_error>

namespace ikebana::game {

std::filesystem::path asset_dir() {
    if (const char* env = std::getenv("IKEBANA_ASSETS"); env && *env) return env;
    return IKEBANA_ASSET_DIR;
}

std::filesystem::path asset_path(const std::filesystem::path& relative) {
    return relative.is_absolute() ? relative : asset_dir() / relative;
}

Result<std::filesystem::path> named_from(const std::filesystem::path& naming_file, const std::filesystem::path& named) {
    if (named.empty()) return make_error(ErrorCode::invalid_argument, "an empty path names no file");
    if (named.is_absolute()) return named;
    std::error_code ec;
    std::string looked;
    if (!naming_file.empty()) {
        const std::filesystem::path beside = (naming_file.parent_path() / named).lexically_normal();
        if (std::filesystem::exists(beside, ec)) return beside;
        const auto whole = std::filesystem::absolute(beside, ec);
        looked = (ec ? beside : whole).string() + " (beside " + naming_file.filename().string() + ") nor ";
    }
    const std::filesystem::path shipped = (asset_dir() / named).lexically_normal();
    if (std::filesystem::exists(shipped, ec)) return shipped;
    return make_error(ErrorCode::not_found, "\"" + named.string() + "\" is not at " + looked + shipped.string() + " (in the assets folder)");
}

} // namespace ikebana::game
