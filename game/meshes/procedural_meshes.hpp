#pragma once
// The shipped petal, leaf, head and hand meshes are generated, not hand-edited: `ikebana assets meshes`
// writes them to assets/meshes/, and a test checks the committed files are exactly what it writes.
// Petals and leaves are one unit long (the species' size_mm scales them); heads and the hand cube
// are at their real size in metres.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/assets/mesh.hpp"
#include "engine/core/result.hpp"

namespace ikebana::game {

struct NamedMesh {
    std::string file; // relative to assets/
    assets::MeshData mesh;
};

[[nodiscard]] std::vector<NamedMesh> procedural_meshes();
// Writes every procedural mesh under `assets_root`; returns the files written.
Result<std::vector<std::filesystem::path>> write_procedural_meshes(const std::filesystem::path& assets_root);

} // namespace ikebana::game
