#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

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

namespace {
// A triangle whose buffer is a file beside the .gltf (`uri`), as downloaded meshes often are.
struct ExternalMesh {
    std::filesystem::path folder;
    std::filesystem::path gltf;
};
ExternalMesh external_mesh(const std::string& folder_name, const std::string& uri) {
    const auto folder = std::filesystem::temp_directory_path() / folder_name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder / "sub");
    auto json = nlohmann::json::parse(gltf_text(triangle()));
    const std::string data_uri = json["buffers"][0]["uri"];
    const std::string base64 = data_uri.substr(data_uri.find(',') + 1);
    // Decode the embedded buffer into a file of its own.
    std::string bin;
    int value = 0, bits = -8;
    for (const char c : base64) {
        const auto at = std::string("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/").find(c);
        if (at == std::string::npos) break;
        value = (value << 6) + static_cast<int>(at);
        bits += 6;
        if (bits >= 0) {
            bin.push_back(static_cast<char>((value >> bits) & 0xff));
            bits -= 8;
        }
    }
    std::ofstream(folder / "tri.bin", std::ios::binary) << bin;
    json["buffers"][0]["uri"] = uri;
    std::ofstream(folder / "sub" / "tri.gltf") << json.dump();
    return {folder, folder / "sub" / "tri.gltf"};
}
} // namespace

TEST(GltfMesh, ABufferBesideTheFileIsRead) {
    const auto m = external_mesh("ikebana_gltf_beside", "tri.bin");
    std::filesystem::rename(m.folder / "tri.bin", m.folder / "sub" / "tri.bin");
    const auto loaded = load_gltf_mesh(m.gltf);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->positions.size(), 3u);
}

// A mesh reads only files in its own folder: not ../ above it, not an absolute path, not from the
// current directory, and nothing at all when it is given as text.
TEST(GltfMesh, URIsOutsideTheMeshesFolderAreRefused) {
    for (const std::string uri : {"../tri.bin", "/etc/passwd", "sub/../../tri.bin", "file:///etc/passwd", "%2e%2e/tri.bin"}) {
        const auto m = external_mesh("ikebana_gltf_escape", uri);
        const auto loaded = load_gltf_mesh(m.gltf);
        ASSERT_FALSE(loaded) << uri << " was read";
        EXPECT_NE(loaded.error().message.find("tri.gltf: /buffers/0/uri: '" + uri + "' is refused: a mesh reads only files in its own folder"),
                  std::string::npos) << loaded.error().message;
        EXPECT_EQ(loaded.error().message.find("root:"), std::string::npos) << "never echo what a file holds";
    }
    const auto m = external_mesh("ikebana_gltf_text", "tri.bin");
    std::filesystem::rename(m.folder / "tri.bin", m.folder / "sub" / "tri.bin");
    std::ifstream in(m.gltf);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_FALSE(parse_gltf_mesh(text, "text.gltf")) << "bytes without a folder have no files beside them";
}

// A fuzzer's finding: tinygltf's JSON reader recurses without a limit (20,000 nested arrays in `extras`
// crashed `species check`). The nesting is refused before tinygltf sees the file, naming where.
TEST(GltfMesh, DeepNestingIsRefusedBeforeTinygltf) {
    const std::string deep = "{\"asset\": {\"version\": \"2.0\"},\n \"extras\": " + std::string(20000, '[') + std::string(20000, ']') + "}";
    const auto loaded = parse_gltf_mesh(deep, "deep.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("deep.gltf:2:"), std::string::npos) << loaded.error().message;
    EXPECT_NE(loaded.error().message.find("nest deeper than 64 levels"), std::string::npos);
}

// Images are never decoded: a picture the mesh names costs nothing and breaks nothing.
TEST(GltfMesh, ImagesAreSkippedNotDecoded) {
    auto json = nlohmann::json::parse(gltf_text(triangle()));
    json["images"] = nlohmann::json::array({{{"uri", "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAF3AAABdwCAIAAAA"}}});
    json["images"].push_back({{"uri", "huge.png"}});
    const auto loaded = parse_gltf_mesh(json.dump(), "picture.gltf");
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->skipped_images, 2u) << "counted, so that `species check` can say they were skipped";
}

// A parser's message says where, never what the file holds.
TEST(GltfMesh, ErrorsDoNotQuoteTheFile) {
    const auto loaded = parse_gltf_mesh(R"({"asset": {"version": "2.0"}, "secret": "root:x:0:0 password123", oops })", "bad.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error().message.find("password123"), std::string::npos) << loaded.error().message;
    EXPECT_NE(loaded.error().message.find("line 1, column 67"), std::string::npos) << loaded.error().message;
}

// A binary .glb is read like a .gltf (a designer's download is often one).
TEST(GltfMesh, BinaryGlbIsRead) {
    auto json = nlohmann::json::parse(gltf_text(triangle()));
    const std::string data_uri = json["buffers"][0]["uri"];
    const auto via_text = parse_gltf_mesh(json.dump(), "t.gltf");
    ASSERT_TRUE(via_text);
    const auto m = external_mesh("ikebana_glb", "tri.bin");
    std::ifstream bin_in(m.folder / "tri.bin", std::ios::binary);
    std::string bin((std::istreambuf_iterator<char>(bin_in)), std::istreambuf_iterator<char>());
    while (bin.size() % 4) bin.push_back('\0');
    json["buffers"][0].erase("uri");
    std::string chunk = json.dump();
    while (chunk.size() % 4) chunk.push_back(' ');
    auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    const std::string glb = "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + 8 + chunk.size() + 8 + bin.size())) +
                            u32(static_cast<std::uint32_t>(chunk.size())) + "JSON" + chunk + u32(static_cast<std::uint32_t>(bin.size())) +
                            std::string("BIN\0", 4) + bin;
    const auto loaded = parse_gltf_mesh(glb, "tri.glb");
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(loaded->positions, via_text->positions);
}
