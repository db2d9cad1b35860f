#include "game/meshes/procedural_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// How wide a part is along its length (0..1 of its widest), for u from its base (0) to its tip (1).
float outline_at(const PartShape& shape, float u) {
    // The body swells from the base to its widest, then the end closes over the last `end` of the
    // length: to a point (linearly), or round (a quarter ellipse).
    float body = 1.0f, end = 0.5f;
    switch (shape.outline) {
    case PartOutline::petal: // widest two-thirds out
        body = u < 0.65f ? std::sin(0.5f * pi * u / 0.65f) : 1.0f;
        end = 0.35f;
        break;
    case PartOutline::leaf: // widest at the middle
        body = u < 0.5f ? std::sin(0.5f * pi * u / 0.5f) : 1.0f;
        end = 0.5f;
        break;
    case PartOutline::sword: // parallel-sided from a short base
        body = std::min(1.0f, u / 0.04f);
        end = std::clamp(2.0f * static_cast<float>(shape.width), 0.02f, 0.3f);
        break;
    }
    if (u <= 1.0f - end) return body;
    const float t = std::min(1.0f, (u - (1.0f - end)) / end); // 0..1 through the end
    return body * (shape.round_tip ? std::sqrt(std::max(0.0f, 1.0f - t * t)) : 1.0f - t);
}

} // namespace

std::string part_mesh_name(const PartShape& shape) {
    const char* outline = shape.outline == PartOutline::petal ? "petal" : shape.outline == PartOutline::leaf ? "leaf" : "sword";
    char name[96];
    std::snprintf(name, sizeof name, "part:%s:w%.3f:%s:f%.0f", outline, shape.width, shape.round_tip ? "round" : "pointed",
                  shape.fold_rad * 180.0 / glm::pi<double>());
    return name;
}

std::optional<assets::MeshData> part_mesh_of_name(const std::string& name) {
    char outline[16] = {};
    char tip[16] = {};
    double width = 0.0, fold_deg = 0.0;
    if (name.rfind("part:", 0) != 0 || name.size() > 80) return std::nullopt;
    if (std::sscanf(name.c_str(), "part:%15[a-z]:w%lf:%15[a-z]:f%lf", outline, &width, tip, &fold_deg) != 4) return std::nullopt;
    PartShape shape;
    const std::string o = outline, t = tip;
    if (o == "petal") shape.outline = PartOutline::petal;
    else if (o == "leaf") shape.outline = PartOutline::leaf;
    else if (o == "sword") shape.outline = PartOutline::sword;
    else return std::nullopt;
    if (t != "round" && t != "pointed") return std::nullopt;
    if (!(width > 0.0 && width <= 1.0) || !(fold_deg >= 0.0 && fold_deg <= 80.0)) return std::nullopt;
    shape.round_tip = t == "round";
    shape.width = width;
    shape.fold_rad = fold_deg * glm::pi<double>() / 180.0;
    auto mesh = part_mesh(shape);
    mesh.name = name;
    return mesh;
}

assets::MeshData part_mesh(const PartShape& shape) {
    // Long and narrow shapes get more steps along: a sword leaf is 12 of its widths long or more.
    const int along = shape.outline == PartOutline::sword ? 24 : 16;
    const float half = 0.5f * static_cast<float>(shape.width);
    const float rise = std::tan(static_cast<float>(shape.fold_rad));
    return grid_surface(part_mesh_name(shape), along, 6, [&](float u, float v) {
        const float y = (2.0f * v - 1.0f) * half * outline_at(shape, u);
        return glm::vec3(u, y, rise * std::abs(y));
    }); // a single sheet, as the shipped petal and leaf: the renderer draws sheets from both sides
}

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
