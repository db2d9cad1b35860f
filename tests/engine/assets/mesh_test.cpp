#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/mesh.hpp"
#include "tests/support/gltf_fixtures.hpp"

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

// A designer's export: a material with a base colour texture, its picture beside the file or inside it.
TEST(GltfMesh, ATexturedQuadBringsItsMaterialAndItsPicture) {
    for (const bool embedded : {false, true}) {
        const auto folder = std::filesystem::temp_directory_path() / (embedded ? "ikebana_quad_embedded" : "ikebana_quad_beside");
        const auto path = test::write_textured_quad(folder, embedded);
        const auto loaded = load_gltf_mesh(path);
        ASSERT_TRUE(loaded) << loaded.error().message;
        ASSERT_EQ(loaded->parts.size(), 1u);
        ASSERT_EQ(loaded->materials.size(), 1u);
        EXPECT_EQ(loaded->materials[0].name, "four colours");
        EXPECT_FLOAT_EQ(loaded->materials[0].roughness, 0.9f);
        ASSERT_EQ(loaded->materials[0].base_colour_image, 0);
        ASSERT_EQ(loaded->images.size(), 1u);
        EXPECT_EQ(loaded->images[0].width, 2u);
        EXPECT_EQ(loaded->images[0].height, 2u);
        const std::vector<std::uint8_t> expected = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 0, 255};
        EXPECT_EQ(loaded->images[0].pixels, expected) << "decoded as written, row 0 at the top";
        ASSERT_EQ(loaded->uvs.size(), 4u);
        EXPECT_EQ(loaded->uvs[2], glm::vec2(1.0f, 1.0f));
    }
}

// Nodes move their primitives down the hierarchy (Blender exports objects as nodes with transforms),
// and each primitive keeps its material.
TEST(GltfMesh, TwoNodesMoveTheirPrimitivesByTheirTransforms) {
    const auto path = test::write_two_node_glb(std::filesystem::temp_directory_path() / "ikebana_two_nodes");
    const auto loaded = load_gltf_mesh(path);
    ASSERT_TRUE(loaded) << loaded.error().message;
    ASSERT_EQ(loaded->parts.size(), 4u) << "two primitives shown by two nodes";
    ASSERT_EQ(loaded->materials.size(), 2u);
    EXPECT_EQ(loaded->materials[0].base_colour, glm::vec4(1.0f, 0.5f, 0.0f, 1.0f));
    EXPECT_FLOAT_EQ(loaded->materials[0].metallic, 1.0f) << "glTF's default";
    EXPECT_EQ(loaded->parts[1].material, 1);
    // The centre and size of each node's triangles.
    auto box = [&](std::size_t first_part) {
        glm::vec3 lo(1e9f), hi(-1e9f);
        for (std::size_t p = first_part; p < first_part + 2; ++p) {
            for (std::uint32_t i = 0; i < loaded->parts[p].index_count; ++i) {
                const auto& v = loaded->positions[loaded->indices[loaded->parts[p].first_index + i]];
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
        }
        return std::pair{(lo + hi) * 0.5f, hi - lo};
    };
    const auto [parent_centre, parent_size] = box(0);
    const auto [child_centre, child_size] = box(2);
    EXPECT_LT(glm::distance(parent_centre, glm::vec3(2, 0, 0)), 1e-5f);
    EXPECT_LT(glm::distance(parent_size, glm::vec3(1, 1, 0)), 1e-5f);
    EXPECT_LT(glm::distance(child_centre, glm::vec3(2, 1, 0)), 1e-5f) << "1 m along the parent's +x, which is turned to +y";
    EXPECT_LT(glm::distance(child_size, glm::vec3(0.5f, 0.5f, 0)), 1e-5f);
    // The parent's first vertex (-0.5, 0.5) turned a quarter about +z and moved: (1.5, -0.5).
    EXPECT_LT(glm::distance(loaded->positions[0], glm::vec3(1.5f, -0.5f, 0)), 1e-5f);
    EXPECT_LT(glm::distance(loaded->normals[0], glm::vec3(0, 0, 1)), 1e-5f);
}

// Nodes form trees: a loop of children, or a node with two parents, would be drawn forever or twice.
TEST(GltfMesh, NodesThatAreNotATreeAreRefused) {
    auto json = nlohmann::json::parse(gltf_text(triangle()));
    json["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
    json.erase("scenes");
    json.erase("scene");
    auto loaded = parse_gltf_mesh(json.dump(), "loop.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("loop.gltf: /nodes/0: the node is its own ancestor"), std::string::npos) << loaded.error().message;
    json["nodes"] = {{{"mesh", 0}, {"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
    loaded = parse_gltf_mesh(json.dump(), "twice.gltf");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("twice.gltf: /nodes/2: a node with two parents"), std::string::npos) << loaded.error().message;
}

// A picture's size is read from its header before it is decoded: a few bytes claiming 5000 x 5000
// pixels are refused, naming the picture, without 100 MB being asked for.
TEST(GltfMesh, APictureLargerThanTheLimitIsRefusedBeforeItIsDecoded) {
    const auto folder = std::filesystem::temp_directory_path() / "ikebana_huge_picture";
    const auto path = test::write_textured_quad(folder, false);
    auto png = assets::read_text_file(folder / "four_colours.png");
    ASSERT_TRUE(png);
    // The IHDR chunk's width and height (big-endian, from byte 16); its CRC is not checked by stb.
    const unsigned char huge[8] = {0x00, 0x00, 0x13, 0x88, 0x00, 0x00, 0x13, 0x88};
    png->replace(16, 8, reinterpret_cast<const char*>(huge), 8);
    ASSERT_TRUE(assets::write_file_atomically(folder / "four_colours.png", *png));
    const auto loaded = load_gltf_mesh(path);
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("/images/0: a picture of 5000x5000 pixels, more than the 4096 a side that is read"), std::string::npos)
        << loaded.error().message;
}

// A material naming a picture that is not there: the file and the picture are named.
TEST(GltfMesh, AMissingPictureIsNamed) {
    const auto folder = std::filesystem::temp_directory_path() / "ikebana_missing_picture";
    const auto path = test::write_textured_quad(folder, false);
    std::filesystem::remove(folder / "four_colours.png");
    const auto loaded = load_gltf_mesh(path);
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("quad.gltf: /images/0: \"four_colours.png\" could not be read"), std::string::npos) << loaded.error().message;
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
