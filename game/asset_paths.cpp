#include "game/asset_paths.hpp"

#include <algorithm>
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

bool below(const std::filesystem::path& folder, const std::filesystem::path& path) {
    std::error_code ec;
    const auto root = std::filesystem::weakly_canonical(folder, ec);
    if (ec) return false;
    const auto target = std::filesystem::weakly_canonical(path, ec);
    if (ec) return false;
    const auto [r, t] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    return r == root.end();
}

Result<std::filesystem::path> named_from(const std::filesystem::path& naming_file, const std::filesystem::path& named) {
    if (named.empty()) return make_error(ErrorCode::invalid_argument, "an empty path names no file");
    if (naming_file.empty() && named.is_absolute()) return named;
    std::error_code ec;
    // A file (or a link to one): a folder of that name is not it.
    const auto is_file = [&](const std::filesystem::path& p) { return std::filesystem::is_regular_file(p, ec); };
    // Without a naming file the path came from the command line or a scene made in code: from the
    // working directory, as a shell user means it.
    const std::filesystem::path folder = naming_file.empty() || naming_file.parent_path().empty() ? std::filesystem::path(".") : naming_file.parent_path();
    const std::filesystem::path first = naming_file.empty() ? named : (named.is_absolute() ? named : (folder / named).lexically_normal());
    const std::filesystem::path shipped = named.is_absolute() ? named : (asset_dir() / named).lexically_normal();
    // Named inside a data file (which may come from anywhere): only files in that file's folder or the
    // assets folder, as a glTF's URIs. Checked before looking, with one answer whether or not the file
    // exists: a species naming /etc/shadow was opened (as root), and the errors told whether it was there.
    const bool first_allowed = naming_file.empty() || below(folder, first) || below(asset_dir(), first);
    const bool shipped_allowed = below(asset_dir(), shipped);
    if (!first_allowed && !shipped_allowed)
        return make_error(ErrorCode::invalid_argument, "\"" + named.string() + "\" is outside " + naming_file.filename().string() +
                                                           "'s folder and the assets folder: a data file names only files inside them");
    if (first_allowed && is_file(first)) return first;
    // Beside the naming file by name, but a link that leads out of its folder: refused as such, not
    // looked for in the assets folder instead (a species whose mesh was such a link was refused by
    // `species check` and loaded by `sim` and `render`, which then drew a placeholder).
    const auto relative = first.lexically_relative(folder.lexically_normal());
    const bool lexically_inside = !relative.empty() && *relative.begin() != "..";
    if (!naming_file.empty() && !first_allowed && !named.is_absolute() && lexically_inside && std::filesystem::is_symlink(first, ec)) {
        return make_error(ErrorCode::invalid_argument, "\"" + named.string() + "\" beside " + naming_file.filename().string() +
                                                           " is a link that leads outside its folder: a data file names only files inside it and the assets folder");
    }
    const auto whole = std::filesystem::absolute(first, ec);
    const std::string looked = (ec ? first : whole).string() + (naming_file.empty() ? std::string(" (from the working directory)") : " (beside " + naming_file.filename().string() + ")") + " nor ";
    if (shipped_allowed && is_file(shipped)) return shipped;
    return make_error(ErrorCode::not_found, "\"" + named.string() + "\" is not at " + looked + shipped.string() + " (in the assets folder)");
}

} // namespace ikebana::game
