#include "game/cli/species_command.hpp"

#include <cstdio>
#include <iostream>

#include "engine/assets/mesh.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/species_preview.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

int check_species_files(const std::vector<std::string>& files) {
    int bad = 0;
    for (const auto& file : files) {
        const auto species = load_species_file(file);
        if (species) {
            // Meshes are checked too: the app would draw a placeholder, but a designer wants to know.
            bool all_ok = true;
            std::vector<std::pair<std::string, std::string>> meshes;
            if (!species->head_mesh.empty()) meshes.emplace_back("/head/mesh", species->head_mesh);
            for (std::size_t i = 0; i < species->parts.size(); ++i) {
                if (!species->parts[i].mesh.empty()) meshes.emplace_back("/parts/" + std::to_string(i) + "/mesh", species->parts[i].mesh);
            }
            std::string notes;
            const std::string name = std::filesystem::path(file).filename().string();
            // A scene names a species by its file's name (species/<id>.json), and the world knows it by its id.
            if (const std::string stem = std::filesystem::path(file).stem().string(); species->id != stem) {
                std::cerr << name << ": /id: \"" << species->id << "\" is not the file's name (" << stem
                          << "): a scene names a species by its file's name and the simulation knows it by its id; make them agree\n";
                all_ok = false;
            }
            for (const auto& [where, mesh] : meshes) {
                const auto found = named_from(file, mesh);
                if (!found) {
                    std::cerr << name << ": " << where << ": " << found.error().message << "\n";
                    all_ok = false;
                    continue;
                }
                const auto loaded = assets::load_gltf_mesh(*found);
                if (!loaded) {
                    std::cerr << name << ": " << where << ": " << loaded.error().message << "\n";
                    all_ok = false;
                } else if (!loaded->materials.empty()) {
                    // Said, so that a designer sees that the file's own colours and pictures were read.
                    notes += "\n  " + where + " (" + mesh + "): " + std::to_string(loaded->parts.size()) + " part(s), " +
                             std::to_string(loaded->materials.size()) + " material(s), " + std::to_string(loaded->images.size()) +
                             " picture(s), drawn times the species' look colour";
                }
            }
            if (!all_ok) {
                ++bad;
                continue;
            }
            std::printf("%s: ok (%s, %s branch, %u segments, %.0f mm)%s\n", file.c_str(), species->id.c_str(),
                        species->branch == BranchKind::hard ? "hard" : "soft", species->segments, species->length_m * 1e3, notes.c_str());
        } else {
            ++bad;
            std::cerr << species.error().message << "\n";
        }
    }
    if (bad > 0) std::cerr << bad << " of " << files.size() << " species file(s) have problems\n";
    return bad > 0 ? 1 : 0;
}

void add_species_command(CLI::App& app, int& exit_code) {
    auto* species = app.add_subcommand("species", "Work with species files (assets/species/*.json)");
    species->require_subcommand(1);
    auto files = std::make_shared<std::vector<std::string>>();
    auto* check = species->add_subcommand("check", "Validate species files; every problem is printed with its JSON path");
    check->add_option("files", *files, "Species files")->required()->check(CLI::ExistingFile);
    check->callback([files, &exit_code] { exit_code = check_species_files(*files); });
    add_species_preview_command(*species, exit_code);
}

} // namespace ikebana::game
