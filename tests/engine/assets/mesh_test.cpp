#include <gtest/gtest.h>

#include <random>

#include "engine/assets/mesh.hpp"

using namespace ikebana;
using namespace ikebana::assets;

namespace {
MeshData triangle() {
    MeshData m;
    m.name = "tri";
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.indices = {0, 1, 2};
    return m;
}
} // namespace

TEST(GltfMesh, WrittenMeshReadsBackIdentically) {
    const auto original = placeholder_mesh();
    const auto loaded = parse_gltf_mesh(gltf_text(original), "p.gltf");
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->positions, original.positions);
    ASSERT_EQ(loaded->normals.size(), original.normals.size());
    for (std::size_t i = 0; i < original.normals.size(); ++i) {
        EXPECT_LT(glm::length(loaded->normals[i] - original.normals[i]), 1e-6f) << "renormalised on load only";
    }
    EXPECT_EQ(loaded->indices, original.indices);
    EXPECT_EQ(loaded->name, "placeholder");
}

TEST(GltfMesh, MissingFileIsNotFound) {
    const auto loaded = load_gltf_mesh("/nonexistent/petal.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error().code, ErrorCode::not_found);
    EXPECT_NE(loaded.error().message.find("petal.gltf"), std::string::npos);
}

TEST(GltfMesh, MeshWithoutNormalsIsRefused) {
    auto text = gltf_text(triangle());
    const auto at = text.find("\"NORMAL\"");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 8, "\"TEXCOORD_7\"");
    const auto loaded = parse_gltf_mesh(text, "t.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("t.gltf"), std::string::npos);
}

TEST(GltfMesh, IndexPastTheVerticesIsRefused) {
    auto m = triangle();
    m.indices = {0, 1, 7};
    const auto loaded = parse_gltf_mesh(gltf_text(m), "t.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("points past the vertices"), std::string::npos);
}

TEST(GltfMesh, AccessorPastItsBufferIsRefused) {
    auto text = gltf_text(triangle());
    const auto at = text.find("\"count\": 3");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 10, "\"count\": 3000");
    const auto loaded = parse_gltf_mesh(text, "t.gltf");
    ASSERT_FALSE(loaded);
}

// Property: mutated files never crash the loader; what loads is a well-formed mesh.
TEST(GltfMesh, MutatedFilesNeverCrashTheLoader) {
    const std::string original = gltf_text(placeholder_mesh());
    std::mt19937_64 rng(99);
    const std::string alphabet = "{}[]\":,0123456789-eE ABCabc/=+";
    for (int iteration = 0; iteration < 1500; ++iteration) {
        std::string text = original;
        for (int k = 0; k < 1 + static_cast<int>(rng() % 3) && !text.empty(); ++k) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 4) {
            case 0: text.erase(at, 1 + rng() % 6); break;
            case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
            case 2: text[at] = alphabet[rng() % alphabet.size()]; break;
            default: text.resize(at); break;
            }
        }
        const auto loaded = parse_gltf_mesh(text, "fuzz.gltf");
        if (loaded) {
            ASSERT_EQ(loaded->positions.size(), loaded->normals.size());
            ASSERT_EQ(loaded->indices.size() % 3, 0u);
            for (const auto i : loaded->indices) ASSERT_LT(i, loaded->positions.size());
        } else {
            EXPECT_EQ(loaded.error().message.rfind("fuzz.gltf", 0), 0u);
        }
    }
}
