#include <gtest/gtest.h>

#include <filesystem>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/assets/mesh.hpp"
#include "game/meshes/procedural_meshes.hpp"

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
