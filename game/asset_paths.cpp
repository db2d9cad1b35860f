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
    // A file (or a link to one): a folder of that name is not it.
    const auto is_file = [&](const std::filesystem::path& p) { return std::filesystem::is_regular_file(p, ec); };
    // Without a naming file the path came from the command line or a scene made in code: from the
    // working directory, as a shell user means it.
    const std::filesystem::path first = naming_file.empty() ? named : (naming_file.parent_path() / named).lexically_normal();
    if (is_file(first)) return first;
    const auto whole = std::filesystem::absolute(first, ec);
    looked = (ec ? first : whole).string() + (naming_file.empty() ? std::string(" (from the working directory)") : " (beside " + naming_file.filename().string() + ")") + " nor ";
    const std::filesystem::path shipped = (asset_dir() / named).lexically_normal();
    if (is_file(shipped)) return shipped;
    return make_error(ErrorCode::not_found, "\"" + named.string() + "\" is not at " + looked + shipped.string() + " (in the assets folder)");
}

} // namespace ikebana::game
