#include "engine/render/mesh_lod.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

namespace ikebana::render {

namespace {

// Which way a normal faces, to within an octant: the two sides of a thin shape, or the faces at a hard
// edge, are not merged into one vertex whose normal averages to nothing.
int octant(const glm::vec3& n) { return (n.x < 0.0f ? 1 : 0) | (n.y < 0.0f ? 2 : 0) | (n.z < 0.0f ? 4 : 0); }

// The corners of a mesh's bounding box (a mesh with positions).
std::pair<glm::vec3, glm::vec3> bounds(const assets::MeshData& mesh) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    for (const auto& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return {lo, hi};
}

struct Merged {
    glm::vec3 position{0.0f};
    double reach = -1.0; // of `position` from the mesh's middle
    glm::dvec3 normal{0.0};
    glm::dvec2 uv{0.0};
    glm::dvec4 tangent{0.0};
    int count = 0;
};

} // namespace

assets::MeshData clustered_mesh(const assets::MeshData& mesh, int cells) {
    if (mesh.positions.empty() || cells < 1) {
        assets::MeshData same = mesh;
        same.images.clear(); // the copy shares its mesh's pictures
        return same;
    }
    assets::MeshData out;
    out.name = mesh.name;
    out.materials = mesh.materials;
    const auto [lo, hi] = bounds(mesh);
    const glm::vec3 span = hi - lo;
    const glm::vec3 middle = 0.5f * (lo + hi);
    const double longest = std::max({span.x, span.y, span.z});
    const double cell = longest > 0.0 && std::isfinite(longest) ? longest / cells : 1.0;
    const auto index_of = [&](float v, float from) {
        const double t = std::floor((static_cast<double>(v) - from) / cell);
        // A position that is not a number (a broken file) goes to the first cell, not to a cast's UB.
        return t >= 0.0 ? static_cast<int>(std::min(t, static_cast<double>(cells))) : 0;
    };
    const bool has_uv = mesh.uvs.size() == mesh.positions.size();
    const bool has_tangent = mesh.tangents.size() == mesh.positions.size();
    const auto normal_of = [&](std::uint32_t v) { return v < mesh.normals.size() ? mesh.normals[v] : glm::vec3(0, 0, 1); };

    // The parts as the renderer takes them: those within the indices, or the whole mesh as one.
    std::vector<assets::MeshPart> parts;
    for (const auto& p : mesh.parts) {
        if (p.first_index <= mesh.indices.size() && p.index_count <= mesh.indices.size() - p.first_index) parts.push_back(p);
    }
    const bool whole = mesh.parts.empty();
    if (whole) parts.push_back({0, static_cast<std::uint32_t>(mesh.indices.size()), -1});

    using Key = std::tuple<std::size_t, int, int, int, int>; // part, cell x y z, normal's octant
    std::map<Key, std::uint32_t> merged_at;
    std::vector<Merged> merged;
    // Per part, old vertex -> merged one (UINT32_MAX: not yet); only the entries a part set are reset
    // for the next, so many parts of a large mesh cost their own vertices, not parts x vertices.
    std::vector<std::uint32_t> remap(mesh.positions.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint32_t> touched;
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const auto& part = parts[k];
        for (const auto v : touched) remap[v] = std::numeric_limits<std::uint32_t>::max();
        touched.clear();
        assets::MeshPart kept{static_cast<std::uint32_t>(out.indices.size()), 0, part.material};
        for (std::uint32_t t = 0; t + 2 < part.index_count; t += 3) {
            std::uint32_t tri[3];
            bool valid = true;
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = mesh.indices[part.first_index + t + static_cast<std::uint32_t>(c)];
                if (v >= mesh.positions.size()) {
                    valid = false;
                    break;
                }
                if (remap[v] == std::numeric_limits<std::uint32_t>::max()) {
                    const glm::vec3 p = mesh.positions[v];
                    const Key key{k, index_of(p.x, lo.x), index_of(p.y, lo.y), index_of(p.z, lo.z), octant(normal_of(v))};
                    auto [it, added] = merged_at.try_emplace(key, static_cast<std::uint32_t>(merged.size()));
                    if (added) merged.emplace_back();
                    Merged& m = merged[it->second];
                    // The cell's vertex farthest out stands for it: a mean pulls a petal's tip and
                    // edges inward and the coarse copy looks thinner than the mesh.
                    if (const double reach = glm::length(glm::dvec3(p - middle)); reach > m.reach) {
                        m.reach = reach;
                        m.position = p;
                    }
                    m.normal += glm::dvec3(normal_of(v));
                    if (has_uv) m.uv += glm::dvec2(mesh.uvs[v]);
                    if (has_tangent) m.tangent += glm::dvec4(glm::vec3(mesh.tangents[v]), m.count == 0 ? mesh.tangents[v].w : 0.0f);
                    m.count += 1;
                    remap[v] = it->second;
                    touched.push_back(v);
                }
                tri[c] = remap[v];
            }
            if (!valid || tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue; // collapsed
            out.indices.insert(out.indices.end(), {tri[0], tri[1], tri[2]});
            kept.index_count += 3;
        }
        if (!whole) out.parts.push_back(kept);
    }
    for (const auto& m : merged) {
        const double n = std::max(1, m.count);
        out.positions.push_back(m.position);
        const double length = glm::length(m.normal);
        out.normals.push_back(length > 1e-9 ? glm::vec3(m.normal / length) : glm::vec3(0, 0, 1));
        if (has_uv) out.uvs.push_back(glm::vec2(m.uv / n));
        if (has_tangent) {
            const glm::dvec3 t(m.tangent);
            const double tl = glm::length(t);
            out.tangents.push_back(glm::vec4(tl > 1e-9 ? glm::vec3(t / tl) : glm::vec3(1, 0, 0), m.tangent.w < 0.0 ? -1.0f : 1.0f));
        }
    }
    return out;
}

glm::vec3 mesh_span(const assets::MeshData& mesh) {
    if (mesh.positions.empty()) return glm::vec3(0.0f);
    const auto [lo, hi] = bounds(mesh);
    return hi - lo;
}

double screen_length_px(const glm::mat4& model, const glm::vec3& span, const glm::dvec3& eye_m, double focal_px) {
    const double longest = std::max({glm::length(glm::vec3(model[0])) * static_cast<double>(span.x), glm::length(glm::vec3(model[1])) * static_cast<double>(span.y),
                                     glm::length(glm::vec3(model[2])) * static_cast<double>(span.z)});
    const double distance = glm::length(glm::dvec3(glm::vec3(model[3])) - eye_m);
    if (!(distance > 1e-6)) return std::numeric_limits<double>::infinity();
    return longest / distance * focal_px;
}

} // namespace ikebana::render
