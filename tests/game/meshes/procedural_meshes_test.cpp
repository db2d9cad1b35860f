#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/assets/mesh.hpp"
#include "game/meshes/procedural_meshes.hpp"

#include <glm/gtc/constants.hpp>

using namespace ikebana;
using namespace ikebana::game;

TEST(ProceduralMeshes, CommittedFilesAreWhatTheToolWrites) {
    for (const auto& [file, mesh] : procedural_meshes()) {
        const auto committed = assets::read_text_file(std::filesystem::path(IKEBANA_ASSET_DIR) / file);
        ASSERT_TRUE(committed) << file << ": run `ikebana assets meshes` and commit the result";
        EXPECT_EQ(*committed, assets::gltf_text(mesh)) << file << " differs from the generator's output";
    }
}

TEST(ProceduralMeshes, EveryMeshLoadsWithUnitNormalsAndSmallSize) {
    for (const auto& [file, mesh] : procedural_meshes()) {
        const auto path = std::filesystem::path(IKEBANA_ASSET_DIR) / file;
        const auto loaded = assets::load_gltf_mesh(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        EXPECT_GT(loaded->indices.size(), 0u);
        for (const auto& n : loaded->normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f) << file;
        EXPECT_LT(std::filesystem::file_size(path), 64u * 1024u) << file << " should stay small";
    }
}

TEST(ProceduralMeshes, SpeciesMeshesExist) {
    for (const char* file : {"meshes/petal.gltf", "meshes/leaf.gltf", "meshes/sunflower_head.gltf"}) {
        EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(IKEBANA_ASSET_DIR) / file)) << file;
    }
}

namespace {
// Half the mesh's widest extent across (y) at positions within `from`..`to` of its length (x).
float half_width_between(const assets::MeshData& m, float from, float to) {
    float widest = 0.0f;
    for (const auto& p : m.positions) {
        if (p.x >= from && p.x <= to) widest = std::max(widest, std::abs(p.y));
    }
    return widest;
}
} // namespace

// A designer's part without a mesh file is drawn as the shape its fields describe: a sword leaf one
// unit long and its width across, parallel-sided; a round tip fuller near its end than a pointed one;
// a fold lifts the edges; the name carries the shape and gives it back.
TEST(PartShapes, EachShapeIsAsLongAndAsWideAsItsFieldsSay) {
    PartShape sword{PartOutline::sword, 0.08, false, 20.0 * glm::pi<double>() / 180.0};
    const auto name = part_mesh_name(sword);
    EXPECT_EQ(name, "part:sword:w0.080:pointed:f20");
    const auto mesh = part_mesh_of_name(name);
    ASSERT_TRUE(mesh.has_value());
    EXPECT_EQ(mesh->name, name);
    ASSERT_GT(mesh->indices.size(), 0u);
    float longest = 0.0f;
    for (const auto& p : mesh->positions) longest = std::max(longest, p.x);
    EXPECT_NEAR(longest, 1.0f, 1e-6f);
    EXPECT_NEAR(2.0f * half_width_between(*mesh, 0.0f, 1.0f), 0.08f, 1e-5f);
    EXPECT_NEAR(half_width_between(*mesh, 0.3f, 0.35f), half_width_between(*mesh, 0.7f, 0.75f), 1e-6f) << "parallel-sided";
    float edge_rise = 0.0f;
    for (const auto& p : mesh->positions) edge_rise = std::max(edge_rise, p.z);
    EXPECT_NEAR(edge_rise, 0.04f * std::tan(20.0f * glm::pi<float>() / 180.0f), 1e-5f) << "folded along the midrib";
    for (const auto& n : mesh->normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-4f);

    PartShape round_petal{PartOutline::petal, 0.5, true, 0.0};
    PartShape pointed_petal{PartOutline::petal, 0.5, false, 0.0};
    const auto round = part_mesh(round_petal), pointed = part_mesh(pointed_petal);
    EXPECT_GT(half_width_between(round, 0.9f, 0.95f), 1.5f * half_width_between(pointed, 0.9f, 0.95f)) << "a round tip is fuller at its end";
    EXPECT_NE(part_mesh_name(round_petal), part_mesh_name(pointed_petal));
    EXPECT_TRUE(part_mesh_of_name(part_mesh_name(round_petal)).has_value());
}

TEST(PartShapes, OtherNamesAreLeftToTheFilesTheyName) {
    for (const char* name : {"meshes/leaf.gltf", "part:", "part:sword", "part:oval:w0.100:pointed:f0", "part:leaf:w0.000:pointed:f0",
                             "part:leaf:w1.500:pointed:f0", "part:leaf:w0.200:blunt:f0", "part:leaf:w0.200:round:f90", "part:leaf:wnan:round:f0"}) {
        EXPECT_FALSE(part_mesh_of_name(name).has_value()) << name;
    }
}
