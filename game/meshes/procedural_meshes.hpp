#pragma once
// The shipped petal, leaf, head and hand meshes are generated, not hand-edited: `ikebana assets meshes`
// writes them to assets/meshes/, and a test checks the committed files are exactly what it writes.
// Petals and leaves are one unit long (the species' size_mm scales them); heads and the hand cube
// are at their real size in metres.
#include <cstdint>
#include <filesystem>
#include <optional>
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

// A petal or leaf a species draws without a mesh file (docs/species-format.md, "Shapes"): one unit
// long along +x from its base, `width` (of its length) across at its widest, +z its upper face.
enum class PartOutline : std::uint8_t { petal, leaf, sword };
struct PartShape {
    PartOutline outline = PartOutline::leaf;
    double width = 0.44;     // widest, as a fraction of the length
    bool round_tip = false;  // pointed otherwise
    double fold_rad = 0.0;   // folded along the midrib, each half rising this far (an iris leaf's V)
};
// The name the draw list and the renderer know the shape by ("part:sword:w0.080:pointed:f20"); equal
// shapes (to a thousandth of the width and a degree of fold) share one.
[[nodiscard]] std::string part_mesh_name(const PartShape& shape);
// The mesh for such a name; nothing for any other name (a file the renderer loads itself).
[[nodiscard]] std::optional<assets::MeshData> part_mesh_of_name(const std::string& name);
[[nodiscard]] assets::MeshData part_mesh(const PartShape& shape);
// Writes every procedural mesh under `assets_root`; returns the files written.
Result<std::vector<std::filesystem::path>> write_procedural_meshes(const std::filesystem::path& assets_root);

} // namespace ikebana::game
