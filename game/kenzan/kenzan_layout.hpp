#pragma once
// Kenzan layouts (assets/kenzan/<id>.json): pin grid and pin shape (Figure 10).
#include <filesystem>
#include <string>

#include "components/kenzan.hpp"
#include "engine/core/result.hpp"

namespace ikebana::game {

Result<components::Kenzan> parse_kenzan(std::string_view text, const std::string& label);
// An id ("standard") is looked up in <assets>/kenzan/; anything with a slash or .json is a path.
Result<components::Kenzan> load_kenzan(const std::string& id_or_path);

} // namespace ikebana::game
