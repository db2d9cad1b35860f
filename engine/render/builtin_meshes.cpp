#include "engine/render/builtin_meshes.hpp"

#include <cmath>

namespace ikebana::render {

namespace {
void quad(assets::MeshData& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const auto& p : {a, b, c, d}) {
        m.positions.push_back(p);
        m.normals.push_back(n);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}
} // namespace

assets::MeshData cube_mesh() {
    assets::MeshData m;
    m.name = "cube";
    const float h = 0.5f;
    quad(m, {-h, -h, h}, {h, -h, h}, {h, h, h}, {-h, h, h}, {0, 0, 1});
    quad(m, {-h, h, -h}, {h, h, -h}, {h, -h, -h}, {-h, -h, -h}, {0, 0, -1});
    quad(m, {h, -h, -h}, {h, h, -h}, {h, h, h}, {h, -h, h}, {1, 0, 0});
    quad(m, {-h, -h, h}, {-h, h, h}, {-h, h, -h}, {-h, -h, -h}, {-1, 0, 0});
    quad(m, {-h, h, -h}, {-h, h, h}, {h, h, h}, {h, h, -h}, {0, 1, 0});
    quad(m, {-h, -h, -h}, {h, -h, -h}, {h, -h, h}, {-h, -h, h}, {0, -1, 0});
    return m;
}

assets::MeshData cylinder_mesh(int sides) {
    assets::MeshData m;
    m.name = "cylinder";
    for (int i = 0; i < sides; ++i) {
        const float a0 = 6.2831853f * static_cast<float>(i) / static_cast<float>(sides);
        const float a1 = 6.2831853f * static_cast<float>(i + 1) / static_cast<float>(sides);
        const glm::vec3 p0{std::cos(a0), std::sin(a0), 0.0f}, p1{std::cos(a1), std::sin(a1), 0.0f};
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {p0, p1, p1 + glm::vec3{0, 0, 1}, p0 + glm::vec3{0, 0, 1}});
        m.normals.insert(m.normals.end(), {p0, p1, p1, p0});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        // Caps as fans from the axis.
        const auto cap = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {{0, 0, 1}, p0 + glm::vec3{0, 0, 1}, p1 + glm::vec3{0, 0, 1}, {0, 0, 0}, p1, p0});
        m.normals.insert(m.normals.end(), {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}});
        m.indices.insert(m.indices.end(), {cap, cap + 1, cap + 2, cap + 3, cap + 4, cap + 5});
    }
    return m;
}

assets::MeshData plane_mesh() {
    assets::MeshData m;
    m.name = "plane";
    quad(m, {-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}, {0, 0, 1});
    return m;
}

} // namespace ikebana::render
