#pragma once
// Level of detail: a coarser copy of a mesh, drawn where the mesh covers few pixels. On lavapipe a
// frame's cost is its triangles (vertex shading and set-up run per triangle whatever its size): a
// 16 mm cherry petal at arm's length is about 30 px long, and its 138 triangles are mostly smaller
// than a pixel. Which copy an instance gets is decided per frame from its size on screen.
#include <cstddef>

#include <glm/glm.hpp>

#include "engine/assets/mesh.hpp"

namespace ikebana::render {

// The mesh with its vertices merged on a grid of `cells` steps along its longest side (vertex
// clustering, after Rossignac and Borrel 1993): vertices of one part that fall in one cell and face
// the same way (their normals' octant) become one, at the one farthest from the mesh's middle (so the
// outline keeps its reach), with their mean normal; triangles that collapse are dropped.
// Parts keep their order and materials (a part may end empty); pictures are not copied (the coarse
// copy shares its fine mesh's). Meant for meshes scaled alike on every axis: a stretched one (a
// cylinder made a stem segment) needs a coarse copy of its own.
assets::MeshData clustered_mesh(const assets::MeshData& mesh, int cells);

// The sides of a mesh's bounding box, in its own units (a head modelled in metres is 0.044 across; the
// built-in cylinder, radius 1, is 2 x 2 x 1).
glm::vec3 mesh_span(const assets::MeshData& mesh);

// How long an instance looks on screen, in pixels: the longest side of its mesh's box (`span`) as its
// model matrix scales each, at its origin's distance from the eye, `focal_px` being the eye's focal
// length in pixels (its image height over twice the tangent of half its vertical field of view). At
// the eye: as large as can be (never the coarse copy).
double screen_length_px(const glm::mat4& model, const glm::vec3& span, const glm::dvec3& eye_m, double focal_px);

} // namespace ikebana::render
