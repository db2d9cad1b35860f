#pragma once
// The renderer's own shapes: a unit cube (centred), a cylinder of radius 1 from z = 0 to 1 (pins and
// stem segments are instances of it), and a unit plane at z = 0 facing +z (the table).
#include "engine/assets/mesh.hpp"

namespace ikebana::render {

assets::MeshData cube_mesh();
assets::MeshData cylinder_mesh(int sides = 12);
assets::MeshData plane_mesh();

} // namespace ikebana::render
