// The coarse copies drawn where a mesh covers few pixels (engine/render/mesh_lod.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/render/mesh_lod.hpp"

using namespace ikebana;
using namespace ikebana::render;

namespace {

// A cupped petal one unit along +x, as the shipped petal is made: a 12 x 6 grid, the triangles that
// collapse at its pointed base dropped, in two parts split at half its triangles with materials 0 and 1.
assets::MeshData cupped_petal() {
    assets::MeshData m;
    m.name = "petal";
    const int nu = 12, nv = 6;
    for (int i = 0; i <= nu; ++i) {
        for (int j = 0; j <= nv; ++j) {
            const float u = static_cast<float>(i) / nu, v = static_cast<float>(j) / nv;
            const float half = 0.16f * std::sin(3.14159265f * std::pow(u, 0.7f));
            const float y = (2.0f * v - 1.0f) * half;
            m.positions.push_back({u, y, 0.18f * u * u + 1.2f * y * y});
            m.normals.push_back(glm::normalize(glm::vec3(-0.36f * u, -2.4f * y, 1.0f)));
            m.uvs.push_back({u, v});
        }
    }
    const auto at = [](int i, int j) { return static_cast<std::uint32_t>(i * (nv + 1) + j); };
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            const std::uint32_t quad[2][3] = {{at(i, j), at(i + 1, j), at(i + 1, j + 1)}, {at(i, j), at(i + 1, j + 1), at(i, j + 1)}};
            for (const auto& t : quad) {
                const glm::vec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
                if (glm::length(n) > 1e-12f) m.indices.insert(m.indices.end(), {t[0], t[1], t[2]});
            }
        }
    }
    const auto half = static_cast<std::uint32_t>(m.indices.size() / 6 * 3);
    m.parts = {{0, half, 0}, {half, static_cast<std::uint32_t>(m.indices.size()) - half, 1}};
    m.materials.resize(2);
    return m;
}

std::size_t triangles(const assets::MeshData& m) { return m.indices.size() / 3; }

glm::vec3 lowest(const assets::MeshData& m) {
    glm::vec3 lo(std::numeric_limits<float>::max());
    for (const auto& p : m.positions) lo = glm::min(lo, p);
    return lo;
}

glm::vec3 highest(const assets::MeshData& m) {
    glm::vec3 hi(std::numeric_limits<float>::lowest());
    for (const auto& p : m.positions) hi = glm::max(hi, p);
    return hi;
}

} // namespace

TEST(MeshLod, APetalsCoarseCopyHasAFractionOfItsTrianglesAndTheSameReach) {
    const auto petal = cupped_petal();
    ASSERT_EQ(triangles(petal), 138u) << "as assets/meshes/petal.gltf";
    const auto coarse = clustered_mesh(petal, 8);
    EXPECT_LT(triangles(coarse), triangles(petal) / 2) << triangles(coarse) << " triangles";
    EXPECT_GT(triangles(coarse), 10u) << "still a petal, not a sliver";
    // Each merged vertex is the cell's farthest out: the outline keeps its length and width.
    EXPECT_NEAR(highest(coarse).x, highest(petal).x, 1e-6);
    EXPECT_NEAR(lowest(coarse).x, lowest(petal).x, 1e-6);
    EXPECT_NEAR(highest(coarse).y, highest(petal).y, 1.0 / 8.0);
    EXPECT_NEAR(lowest(coarse).y, lowest(petal).y, 1.0 / 8.0);
    // Every index names a vertex, every vertex has its normal (unit) and picture coordinates.
    ASSERT_EQ(coarse.normals.size(), coarse.positions.size());
    ASSERT_EQ(coarse.uvs.size(), coarse.positions.size());
    EXPECT_TRUE(coarse.tangents.empty());
    for (const auto i : coarse.indices) ASSERT_LT(i, coarse.positions.size());
    for (const auto& n : coarse.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(MeshLod, PartsKeepTheirOrderMaterialsAndOnlyTheirOwnTriangles) {
    const auto petal = cupped_petal();
    const auto coarse = clustered_mesh(petal, 8);
    ASSERT_EQ(coarse.parts.size(), 2u);
    EXPECT_EQ(coarse.parts[0].material, 0);
    EXPECT_EQ(coarse.parts[1].material, 1);
    EXPECT_EQ(coarse.parts[0].first_index, 0u);
    EXPECT_EQ(coarse.parts[1].first_index, coarse.parts[0].index_count);
    EXPECT_EQ(coarse.parts[0].index_count + coarse.parts[1].index_count, coarse.indices.size());
    EXPECT_GT(coarse.parts[0].index_count, 0u);
    EXPECT_GT(coarse.parts[1].index_count, 0u);
    // A vertex of one part is never shared with the other: each part's own picture coordinates.
    std::vector<int> owner(coarse.positions.size(), -1);
    for (int k = 0; k < 2; ++k) {
        const auto& part = coarse.parts[static_cast<std::size_t>(k)];
        for (std::uint32_t i = part.first_index; i < part.first_index + part.index_count; ++i) {
            auto& o = owner[coarse.indices[i]];
            EXPECT_TRUE(o == -1 || o == k) << "vertex " << coarse.indices[i] << " in both parts";
            o = k;
        }
    }
}

TEST(MeshLod, TheTwoSidesOfAThinBoxAreNotMergedIntoOne) {
    // A box 1 x 1 x 0.01 with its own vertices per face (a hard-edged mesh): top and bottom fall in one
    // cell row but face away from each other, so they stay two surfaces with their own normals.
    assets::MeshData box;
    const auto face = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
        const auto base = static_cast<std::uint32_t>(box.positions.size());
        for (const auto& p : {a, b, c, d}) {
            box.positions.push_back(p);
            box.normals.push_back(n);
        }
        box.indices.insert(box.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    };
    face({0, 0, 0.01f}, {1, 0, 0.01f}, {1, 1, 0.01f}, {0, 1, 0.01f}, {0, 0, 1});
    face({0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 0, -1});
    const auto coarse = clustered_mesh(box, 4);
    ASSERT_EQ(triangles(coarse), 4u);
    int up = 0, down = 0, between = 0;
    for (const auto& n : coarse.normals) {
        if (n.z > 0.99f) ++up;
        else if (n.z < -0.99f) ++down;
        else ++between;
    }
    EXPECT_EQ(up, 4);
    EXPECT_EQ(down, 4);
    EXPECT_EQ(between, 0) << "no normal averaged across the two sides";
}

TEST(MeshLod, BrokenIndicesAndPartsAreLeftOutNotFollowed) {
    auto petal = cupped_petal();
    petal.indices[5] = 1'000'000;                                          // past the vertices
    petal.parts.push_back({static_cast<std::uint32_t>(petal.indices.size()), 30, 0}); // past the indices
    const auto coarse = clustered_mesh(petal, 8);
    for (const auto i : coarse.indices) ASSERT_LT(i, coarse.positions.size());
    EXPECT_EQ(coarse.parts.size(), 2u) << "the part beyond the indices is not one the renderer draws either";
}

TEST(MeshLod, NoCellsOrNoVerticesGiveTheMeshBack) {
    const auto petal = cupped_petal();
    EXPECT_EQ(clustered_mesh(petal, 0).indices, petal.indices);
    EXPECT_TRUE(clustered_mesh(assets::MeshData{}, 8).indices.empty());
}

TEST(MeshLod, AnInstancesScreenLengthIsItsMeshsLongestSideAsPlacedOverItsDistance) {
    // A petal one unit long scaled to 16 mm, 0.5 m from the eye, at a focal length of 986 px (720 px
    // high, 0.7 rad): 31.6 px.
    const auto petal = cupped_petal();
    const glm::vec3 petal_span = mesh_span(petal);
    EXPECT_NEAR(petal_span.x, 1.0f, 1e-6f);
    glm::mat4 model(0.0f);
    model[0] = glm::vec4(0.016f, 0, 0, 0);
    model[1] = glm::vec4(0, 0.016f, 0, 0);
    model[2] = glm::vec4(0, 0, 0.016f, 0);
    model[3] = glm::vec4(0, 0.5f, 0, 1);
    EXPECT_NEAR(screen_length_px(model, petal_span, {0, 0, 0}, 986.0), 0.016 / 0.5 * 986.0, 0.01);
    // A head modelled in metres (44 mm across) placed with unit axes: its own size, not a metre.
    EXPECT_NEAR(screen_length_px(glm::translate(glm::mat4(1.0f), glm::vec3(0, 0.5f, 0)), {0.044f, 0.044f, 0.01f}, {0, 0, 0}, 986.0),
                0.044 / 0.5 * 986.0, 0.01);
    // A stem segment, the radius-1 cylinder (2 x 2 x 1) at 4 mm radius and 50 mm long: its length; a
    // disc (the same cylinder, 60 mm radius, 5 mm thick): its diameter.
    const glm::vec3 cylinder{2.0f, 2.0f, 1.0f};
    model[0] = glm::vec4(0.004f, 0, 0, 0);
    model[1] = glm::vec4(0, 0.004f, 0, 0);
    model[2] = glm::vec4(0, 0, 0.05f, 0);
    EXPECT_NEAR(screen_length_px(model, cylinder, {0, 0, 0}, 986.0), 0.05 / 0.5 * 986.0, 0.01);
    glm::mat4 disc = model;
    disc[0] = glm::vec4(0.06f, 0, 0, 0);
    disc[1] = glm::vec4(0, 0.06f, 0, 0);
    disc[2] = glm::vec4(0, 0, 0.005f, 0);
    EXPECT_NEAR(screen_length_px(disc, cylinder, {0, 0, 0}, 986.0), 0.12 / 0.5 * 986.0, 0.01);
    // Twice as far: half as long.
    EXPECT_NEAR(screen_length_px(model, cylinder, {0, -0.5, 0}, 986.0), 0.05 / 1.0 * 986.0, 0.01);
    EXPECT_TRUE(std::isinf(screen_length_px(model, cylinder, {0, 0.5, 0}, 986.0))) << "at the eye: never coarse";
}
