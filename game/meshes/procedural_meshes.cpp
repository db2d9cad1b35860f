#include "game/meshes/procedural_meshes.hpp"

#include <cmath>
#include <functional>

#include <glm/gtc/constants.hpp>

#include "engine/assets/files.hpp"

namespace ikebana::game {

using assets::MeshData;

namespace {

constexpr float pi = glm::pi<float>();

// A (u, v) grid mapped through `surface`, with smooth normals from the surrounding triangles.
MeshData grid_surface(const std::string& name, int nu, int nv, const std::function<glm::vec3(float, float)>& surface) {
    MeshData m;
    m.name = name;
    for (int i = 0; i <= nu; ++i) {
        for (int j = 0; j <= nv; ++j) {
            m.positions.push_back(surface(static_cast<float>(i) / static_cast<float>(nu), static_cast<float>(j) / static_cast<float>(nv)));
        }
    }
    m.normals.assign(m.positions.size(), glm::vec3(0.0f));
    auto at = [nv](int i, int j) { return static_cast<std::uint32_t>(i * (nv + 1) + j); };
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            const std::uint32_t quad[2][3] = {{at(i, j), at(i + 1, j), at(i + 1, j + 1)}, {at(i, j), at(i + 1, j + 1), at(i, j + 1)}};
            for (const auto& tri : quad) {
                const glm::vec3 n = glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]);
                if (glm::length(n) < 1e-12f) continue; // degenerate (a pointed tip): no triangle
                for (const auto k : tri) {
                    m.indices.push_back(k);
                    m.normals[k] += n;
                }
            }
        }
    }
    for (auto& n : m.normals) n = glm::length(n) > 1e-12f ? glm::normalize(n) : glm::vec3(0, 0, 1);
    return m;
}

MeshData petal() {
    // Along +x, one unit long, cupped upwards towards the tip.
    return grid_surface("petal", 12, 6, [](float u, float v) {
        const float half_width = 0.16f * std::sin(pi * std::pow(u, 0.7f));
        const float y = (2.0f * v - 1.0f) * half_width;
        return glm::vec3(u, y, 0.18f * u * u + 1.2f * y * y);
    });
}

MeshData leaf() {
    // Along +x, pointed at both ends, folded along the midrib, arching down at the tip.
    return grid_surface("leaf", 16, 8, [](float u, float v) {
        const float half_width = 0.22f * std::sin(pi * u) * (1.0f - 0.3f * u);
        const float s = 2.0f * v - 1.0f;
        const float y = s * half_width;
        return glm::vec3(u, y, 0.25f * std::abs(y) - 0.12f * u * u);
    });
}

MeshData head(const std::string& name, float radius, float dome) {
    // A polar grid: u is the radius, v the angle; the centre ring collapses to a point.
    return grid_surface(name, 8, 24, [radius, dome](float u, float v) {
        const float a = 2.0f * pi * v;
        const float r = radius * u;
        return glm::vec3(r * std::cos(a), r * std::sin(a), dome * (1.0f - u * u));
    });
}

MeshData cube(float edge) {
    MeshData m;
    m.name = "hand_cube";
    const float h = 0.5f * edge;
    const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& n : normals) {
        // Two axes spanning the face, ordered so that (a x b) points along n.
        const glm::vec3 a = std::abs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        const glm::vec3 b = glm::cross(n, a);
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const auto& corner : {-a - b, a - b, a + b, -a + b}) {
            m.positions.push_back(h * (n + corner));
            m.normals.push_back(n);
        }
        for (const std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
    }
    return m;
}

} // namespace

std::vector<NamedMesh> procedural_meshes() {
    return {
        {"meshes/petal.gltf", petal()},
        {"meshes/leaf.gltf", leaf()},
        {"meshes/sunflower_head.gltf", head("sunflower_head", 0.040f, 0.008f)},
        {"meshes/chrysanthemum_head.gltf", head("chrysanthemum_head", 0.022f, 0.015f)},
        {"meshes/hand_cube.gltf", cube(1.0f)},
    };
}

Result<std::vector<std::filesystem::path>> write_procedural_meshes(const std::filesystem::path& assets_root) {
    std::vector<std::filesystem::path> written;
    for (const auto& [file, mesh] : procedural_meshes()) {
        const auto path = assets_root / file;
        if (auto folder = assets::create_output_folder(path.parent_path()); !folder) return std::move(folder).error();
        if (auto ok = assets::write_gltf_mesh(path, mesh); !ok) return std::move(ok).error();
        written.push_back(path);
    }
    return written;
}

} // namespace ikebana::game
