// On Mesa's lavapipe here and in CI (any Vulkan 1.3 device elsewhere), with the validation layer on.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "engine/render/stereo_renderer.hpp"
#include "tests/support/gltf_fixtures.hpp"

using namespace ikebana;
using namespace ikebana::render;

namespace {

std::unique_ptr<VulkanContext>& shared_context() {
    static std::unique_ptr<VulkanContext> ctx = [] {
        auto c = VulkanContext::create({.validation = true, .require_validation = false, .instance_extensions = {}});
        return c ? std::move(c).value() : nullptr;
    }();
    return ctx;
}

RendererOptions sized(std::uint32_t w, std::uint32_t h) {
    RendererOptions o;
    o.eye_width = w;
    o.eye_height = h;
    return o;
}

MeshInstance cube_at(glm::vec3 p, float size, glm::vec4 colour) {
    glm::mat4 m(size);
    m[3] = glm::vec4(p, 1.0f);
    return {m, colour};
}

// Centroid x of the pixels close to a colour.
double centroid_x(const RgbaImage& img, glm::vec3 colour) {
    double sum = 0.0, n = 0.0;
    for (std::uint32_t y = 0; y < img.height; ++y) {
        for (std::uint32_t x = 0; x < img.width; ++x) {
            const std::uint8_t* p = &img.pixels[4ull * (y * img.width + x)];
            // Hue test: which channel dominates, robust to shading.
            const glm::vec3 c(p[0], p[1], p[2]);
            const float top = std::max(c.r, std::max(c.g, c.b));
            if (top < 30.0f) continue;
            const glm::vec3 normalised = c / top;
            if (glm::distance(normalised, colour) < 0.35f) {
                sum += x;
                n += 1.0;
            }
        }
    }
    return n > 20 ? sum / n : NAN;
}

DrawList two_cubes() {
    DrawList list;
    // Near red cube in front of the zero-parallax plane, far blue cube behind it.
    list.batch("cube").instances = {cube_at({-0.05f, -0.35f, 0.2f}, 0.04f, {0.9f, 0.05f, 0.05f, 1}),
                                    cube_at({0.1f, 0.6f, 0.15f}, 0.12f, {0.05f, 0.05f, 0.9f, 1})};
    list.batch("plane").instances = {{glm::mat4(glm::vec4(2, 0, 0, 0), glm::vec4(0, 2, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1)),
                                      {0.8f, 0.8f, 0.75f, 1}}};
    return list;
}

} // namespace

class StereoRendererTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (!shared_context()) GTEST_SKIP() << "no Vulkan 1.3 device";
    }
};

TEST_F(StereoRendererTest, EyesDifferByParallaxNearMoreThanFar) {
    auto renderer = StereoRenderer::create(*shared_context(), sized(320, 180));
    ASSERT_TRUE(renderer) << renderer.error().message;
    StereoRig rig;
    rig.eye_separation_m = 0.065;
    const auto frame = (*renderer)->render(two_cubes(), rig, true);
    ASSERT_TRUE(frame) << frame.error().message;
    const double near_l = centroid_x(frame->left, {1, 0, 0}), near_r = centroid_x(frame->right, {1, 0, 0});
    const double far_l = centroid_x(frame->left, {0, 0, 1}), far_r = centroid_x(frame->right, {0, 0, 1});
    ASSERT_FALSE(std::isnan(near_l) || std::isnan(near_r) || std::isnan(far_l) || std::isnan(far_r)) << "both cubes in both eyes";
    EXPECT_GT(near_l - near_r, 2.0) << "the near cube is crossed: further right in the left eye";
    EXPECT_LT(far_l - far_r, 0.0) << "the far cube, behind the screen plane, is uncrossed";
    EXPECT_GT(std::abs(near_l - near_r), std::abs(far_l - far_r));
    EXPECT_EQ(shared_context()->validation_errors(), 0u);
}

TEST_F(StereoRendererTest, CompositeModesLayOutTheEyesAsTheDisplayWants) {
    auto renderer = StereoRenderer::create(*shared_context(), sized(160, 90));
    ASSERT_TRUE(renderer) << renderer.error().message;
    StereoRig rig;
    auto sbs = (*renderer)->render(two_cubes(), rig, true);
    ASSERT_TRUE(sbs);
    ASSERT_EQ(sbs->composed.width, 320u);
    // The left half is the left eye, the right half the right eye, pixel for pixel.
    for (std::uint32_t y = 0; y < 90; y += 7) {
        for (std::uint32_t x = 0; x < 160; x += 5) {
            ASSERT_EQ(sbs->composed.pixels[4 * (y * 320 + x)], sbs->left.pixels[4 * (y * 160 + x)]);
            ASSERT_EQ(sbs->composed.pixels[4 * (y * 320 + 160 + x) + 2], sbs->right.pixels[4 * (y * 160 + x) + 2]);
        }
    }
    ASSERT_TRUE((*renderer)->set_mode(StereoMode::rows));
    auto rows = (*renderer)->render(two_cubes(), rig, true);
    ASSERT_TRUE(rows);
    ASSERT_EQ(rows->composed.width, 160u);
    for (std::uint32_t x = 0; x < 160; x += 3) {
        EXPECT_EQ(rows->composed.pixels[4 * (10 * 160 + x)], rows->left.pixels[4 * (10 * 160 + x)]) << "even rows: left";
        EXPECT_EQ(rows->composed.pixels[4 * (11 * 160 + x)], rows->right.pixels[4 * (11 * 160 + x)]) << "odd rows: right";
    }
    ASSERT_TRUE((*renderer)->set_mode(StereoMode::anaglyph));
    auto anaglyph = (*renderer)->render(two_cubes(), rig, true);
    ASSERT_TRUE(anaglyph);
    for (std::uint32_t p = 0; p < 160 * 90; p += 37) {
        EXPECT_EQ(anaglyph->composed.pixels[4 * p], anaglyph->left.pixels[4 * p]) << "red from the left eye";
        EXPECT_EQ(anaglyph->composed.pixels[4 * p + 1], anaglyph->right.pixels[4 * p + 1]) << "green and blue from the right";
    }
    ASSERT_TRUE((*renderer)->set_mode(StereoMode::mono));
    auto mono = (*renderer)->render(two_cubes(), rig, true);
    ASSERT_TRUE(mono);
    const auto same = compare_images(mono->left, mono->right);
    ASSERT_TRUE(same);
    EXPECT_LT(same->mean_abs, 0.05) << "mono: no eye separation, the same picture twice (every batch in both views)";
    EXPECT_EQ(shared_context()->validation_errors(), 0u);
}

TEST_F(StereoRendererTest, MissingMeshIsAPlaceholderWithAWarning) {
    auto renderer = StereoRenderer::create(*shared_context(), sized(64, 64));
    ASSERT_TRUE(renderer);
    DrawList list;
    list.batch("meshes/no_such_flower.gltf").instances = {cube_at({0, 0, 0.1f}, 0.1f, {1, 1, 0, 1})};
    const auto frame = (*renderer)->render(list, StereoRig{}, false);
    ASSERT_TRUE(frame) << frame.error().message;
    const auto warnings = (*renderer)->take_warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("no_such_flower.gltf"), std::string::npos);
}

TEST_F(StereoRendererTest, ResizeChangesOnlyTheOutputSize) {
    auto renderer = StereoRenderer::create(*shared_context(), sized(64, 48));
    ASSERT_TRUE(renderer);
    ASSERT_TRUE((*renderer)->resize(100, 60));
    const auto frame = (*renderer)->render(two_cubes(), StereoRig{}, true);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->composed.width, 200u);
    EXPECT_EQ(frame->left.height, 60u);
    EXPECT_FALSE((*renderer)->resize(0, 10));
}

TEST_F(StereoRendererTest, MultiviewPassDrawsWhatTwoPassesDraw) {
    // Geometry well inside the frustum (no clipping), where lavapipe's multiview is right too.
    DrawList list;
    list.batch("cube").instances = {cube_at({-0.05f, -0.3f, 0.2f}, 0.04f, {0.9f, 0.1f, 0.1f, 1}), cube_at({0.05f, 0.2f, 0.12f}, 0.08f, {0.1f, 0.2f, 0.9f, 1})};
    auto options = sized(200, 120);
    options.multiview = RendererOptions::Multiview::on;
    auto one_pass = StereoRenderer::create(*shared_context(), options);
    options.multiview = RendererOptions::Multiview::off;
    auto two_passes = StereoRenderer::create(*shared_context(), options);
    ASSERT_TRUE(one_pass && two_passes);
    EXPECT_TRUE((*one_pass)->multiview());
    EXPECT_FALSE((*two_passes)->multiview());
    const auto a = (*one_pass)->render(list, StereoRig{}, true);
    const auto b = (*two_passes)->render(list, StereoRig{}, true);
    ASSERT_TRUE(a && b);
    for (auto eye : {&RenderedFrame::left, &RenderedFrame::right}) {
        const auto d = compare_images((*a).*eye, (*b).*eye);
        ASSERT_TRUE(d);
        EXPECT_LT(d->mean_abs, 0.5);
        EXPECT_LT(d->share_over_threshold, 0.002);
    }
    EXPECT_EQ(shared_context()->validation_errors(), 0u);
}

// A window's renderer draws in the swapchain's B8G8R8A8; what it reads back is the same picture.
TEST_F(StereoRendererTest, BgraEyesGiveTheSamePictureAsRgba) {
    const auto list = two_cubes();
    auto rgba_options = sized(160, 96);
    auto bgra_options = rgba_options;
    bgra_options.colour_format = VK_FORMAT_B8G8R8A8_UNORM;
    auto rgba = StereoRenderer::create(*shared_context(), rgba_options);
    auto bgra = StereoRenderer::create(*shared_context(), bgra_options);
    ASSERT_TRUE(rgba && bgra);
    const auto a = (*rgba)->render(list, StereoRig{}, true);
    const auto b = (*bgra)->render(list, StereoRig{}, true);
    ASSERT_TRUE(a && b);
    for (auto image : {&RenderedFrame::composed, &RenderedFrame::left}) {
        const auto d = compare_images((*a).*image, (*b).*image);
        ASSERT_TRUE(d);
        EXPECT_LT(d->mean_abs, 0.01) << "red stays red";
    }
    auto bad = sized(16, 16);
    bad.colour_format = VK_FORMAT_R16G16B16A16_SFLOAT;
    EXPECT_FALSE(StereoRenderer::create(*shared_context(), bad)) << "only the two 8-bit layouts";
    EXPECT_EQ(shared_context()->validation_errors(), 0u);
}

// Pins (and anything else marked so) stay out of the shadow pass, and closed meshes cull their back
// faces: the picture of a closed cube is the same either way.
TEST_F(StereoRendererTest, BatchesThatCastNoShadowLeaveNone) {
    DrawList lit;
    lit.batch("plane").instances = {{glm::mat4(glm::vec4(2, 0, 0, 0), glm::vec4(0, 2, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1)),
                                     {0.8f, 0.8f, 0.75f, 1}}};
    lit.batch("cube").instances = {cube_at({0.0f, 0.0f, 0.06f}, 0.05f, {0.2f, 0.6f, 0.2f, 1})};
    DrawList unshadowed = lit;
    unshadowed.batch("cube").casts_shadow = false;
    auto renderer = StereoRenderer::create(*shared_context(), sized(160, 96));
    ASSERT_TRUE(renderer);
    const auto with_shadow = (*renderer)->render(lit, StereoRig{}, false);
    const auto without = (*renderer)->render(unshadowed, StereoRig{}, false);
    ASSERT_TRUE(with_shadow && without);
    auto brightness = [](const RgbaImage& img) {
        double sum = 0.0;
        for (std::size_t i = 0; i < img.pixels.size(); i += 4) sum += img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2];
        return sum;
    };
    EXPECT_GT(brightness(without->composed), brightness(with_shadow->composed) * 1.001) << "no shadow on the plane: brighter";
    EXPECT_EQ(shared_context()->validation_errors(), 0u);
}

TEST(DrawListTest, ABatchStaysWhereItIsWhileOthersAreAdded) {
    DrawList list;
    auto& cubes = list.batch("cube").instances;
    for (int i = 0; i < 40; ++i) list.batch("mesh" + std::to_string(i), i % 2 == 0);
    cubes.push_back(cube_at({0.0f, 0.0f, 0.0f}, 1.0f, {1, 1, 1, 1}));
    EXPECT_EQ(&list.batch("cube").instances, &cubes) << "a reference held across batch() must not dangle";
    EXPECT_EQ(list.batch("cube").instances.size(), 1u);
    EXPECT_EQ(list.batches.size(), 41u);
}

namespace {

// Looking at the origin from 0.5 m in front (-y), one picture (mono), a quad turned to face the eye:
// its +y (the picture's top row) up, its +z toward the eye.
StereoRig facing_rig() {
    StereoRig rig;
    rig.position_m = {0.0, -0.5, 0.0};
    rig.target_m = {0.0, 0.0, 0.0};
    return rig;
}

MeshInstance facing_quad(float size_m, glm::vec3 at = glm::vec3(0.0f)) {
    glm::mat4 m(0.0f);
    m[0] = glm::vec4(size_m, 0, 0, 0);  // +x stays
    m[1] = glm::vec4(0, 0, size_m, 0);  // +y up
    m[2] = glm::vec4(0, -size_m, 0, 0); // +z toward the eye
    m[3] = glm::vec4(at, 1.0f);
    return {m, {1, 1, 1, 1}};
}

// The share of a region's pixels whose hue is close to `colour` (each channel over the brightest).
double share_of(const RgbaImage& img, glm::vec3 colour, std::uint32_t x0, std::uint32_t y0, std::uint32_t x1, std::uint32_t y1) {
    double n = 0.0, hits = 0.0;
    for (std::uint32_t y = y0; y < y1; ++y) {
        for (std::uint32_t x = x0; x < x1; ++x) {
            const std::uint8_t* p = &img.pixels[4ull * (y * img.width + x)];
            const glm::vec3 c(p[0], p[1], p[2]);
            const float top = std::max(c.r, std::max(c.g, c.b));
            n += 1.0;
            if (top > 30.0f && glm::distance(c / top, colour) < 0.2f) hits += 1.0;
        }
    }
    return n > 0 ? hits / n : 0.0;
}

// One mono picture of `mesh` (a file in `folder`) drawn as `instance`, seen by facing_rig().
RgbaImage picture_of(const std::filesystem::path& folder, const std::string& mesh, MeshInstance instance,
                     glm::vec3 background = DrawList{}.background) {
    auto options = sized(200, 200);
    options.mode = StereoMode::mono;
    options.asset_dir = folder;
    auto renderer = StereoRenderer::create(*shared_context(), options);
    EXPECT_TRUE(renderer) << renderer.error().message;
    if (!renderer) return {};
    DrawList list;
    list.batch(mesh).instances = {instance};
    list.background = background;
    auto frame = (*renderer)->render(list, facing_rig(), false);
    EXPECT_TRUE(frame) << frame.error().message;
    EXPECT_TRUE((*renderer)->take_warnings().empty()) << "drawn from the file, not as a placeholder";
    if (!frame) return {};
    (void)write_png(folder / "seen.png", frame->composed); // to look at
    return std::move(frame->composed);
}

} // namespace

// The check: a generated textured glTF (a quad whose 2x2 picture is red, green, blue and
// yellow) is drawn with its picture, each colour in its own quarter, whether the picture is a PNG
// beside the file or inside it.
TEST_F(StereoRendererTest, ATexturedGltfShowsItsPicturesColours) {
    for (const bool embedded : {false, true}) {
        const auto folder = std::filesystem::temp_directory_path() / (embedded ? "ikebana_render_quad_embedded" : "ikebana_render_quad_beside");
        test::write_textured_quad(folder, embedded);
        const auto img = picture_of(folder, "quad.gltf", facing_quad(0.3f));
        ASSERT_EQ(img.width, 200u);
        // The quad covers about 0.3 of 0.36 m of the view: the middle of each quarter is well inside it.
        const std::uint32_t a = 55, b = 90, c = 110, d = 145;
        EXPECT_GT(share_of(img, {1, 0, 0}, a, a, b, b), 0.9) << "red at the top left";
        EXPECT_GT(share_of(img, {0, 1, 0}, c, a, d, b), 0.9) << "green at the top right";
        EXPECT_GT(share_of(img, {0, 0, 1}, a, c, b, d), 0.9) << "blue at the bottom left";
        EXPECT_GT(share_of(img, {1, 1, 0}, c, c, d, d), 0.9) << "yellow at the bottom right";
        EXPECT_LT(share_of(img, {1, 0, 0}, c, c, d, d), 0.01) << "and nothing red where yellow is";
    }
}

// A leaf cut out of a quad (alphaMode MASK): where its picture is transparent, what lies behind shows.
TEST_F(StereoRendererTest, AMaskedMaterialLetsTheBackgroundThroughItsClearTexels) {
    const auto folder = std::filesystem::temp_directory_path() / "ikebana_render_quad_masked";
    test::write_textured_quad(folder, true, true);
    // Cyan behind it: nothing in the picture is.
    const auto img = picture_of(folder, "quad.gltf", facing_quad(0.3f), {0.2f, 0.9f, 0.9f});
    ASSERT_EQ(img.width, 200u);
    const std::uint32_t a = 55, b = 90, c = 110, d = 145;
    EXPECT_GT(share_of(img, {1, 0, 0}, a, a, b, b), 0.9) << "red, opaque, drawn";
    EXPECT_LT(share_of(img, {0, 0, 1}, a, c, b, d), 0.01) << "the clear blue texel is not drawn";
    EXPECT_GT(share_of(img, glm::vec3(0.2f, 0.9f, 0.9f) / 0.9f, a, c, b, d), 0.9) << "the background shows through it";
}

// Two nodes of a .glb, each showing a mesh of two primitives with a material each: all four drawn,
// where the nodes put them, in their materials' colours.
TEST_F(StereoRendererTest, AGlbsNodesAndMaterialsAreDrawnWhereAndAsTheFileSays) {
    const auto folder = std::filesystem::temp_directory_path() / "ikebana_render_two_nodes";
    test::write_two_node_glb(folder);
    // The file's parent quad is 1 m at (2, 0, 0) and its child's 0.5 m at (2, 1, 0); at a tenth, turned
    // to face the eye and moved to the middle: the parent below the centre, the child above it.
    const auto img = picture_of(folder, "two_nodes.glb", facing_quad(0.1f, {-0.2f, 0.0f, -0.05f}));
    ASSERT_EQ(img.width, 200u);
    const glm::vec3 orange(1.0f, 0.5f, 0.0f), violet(0.5f, 0.0f, 1.0f);
    // The parent's square, about 55 pixels across, is in the lower half; the child's, half as wide, above.
    EXPECT_GT(share_of(img, orange, 0, 100, 200, 200) + share_of(img, violet, 0, 100, 200, 200), 0.05) << "the parent, below";
    EXPECT_GT(share_of(img, orange, 0, 0, 200, 100), 0.005) << "the child's orange half, above";
    EXPECT_GT(share_of(img, violet, 0, 0, 200, 100), 0.005) << "the child's violet half, above";
    EXPECT_GT(share_of(img, violet, 0, 100, 200, 200), 0.01) << "the parent's violet half";
}

// An instance's bend curls its mesh along +x (a cupped petal): a quad bent half a turn per unit is a
// half-cylinder of radius 1/pi, its edges 1/pi of its size out and as far toward the eye (its +z), so
// seen from 0.5 m it looks (0.3/pi) / (0.5 - 0.3/pi) against 0.15 / 0.5 as wide as flat: 0.79; its
// colours kept.
TEST_F(StereoRendererTest, ABentInstanceIsDrawnCurled) {
    const auto folder = std::filesystem::temp_directory_path() / "ikebana_render_bent_quad";
    test::write_textured_quad(folder, true);
    auto width_of = [](const RgbaImage& img) {
        const glm::vec3 background = DrawList{}.background * 255.0f;
        std::uint32_t lo = img.width, hi = 0;
        for (std::uint32_t x = 0; x < img.width; ++x) {
            const std::uint8_t* p = &img.pixels[4ull * (img.height / 2 * img.width + x)];
            if (glm::distance(glm::vec3(p[0], p[1], p[2]), background) > 20.0f) {
                lo = std::min(lo, x);
                hi = std::max(hi, x);
            }
        }
        return hi >= lo ? static_cast<double>(hi - lo + 1) : 0.0;
    };
    const auto flat = picture_of(folder, "quad.gltf", facing_quad(0.3f));
    auto bent_quad = facing_quad(0.3f);
    bent_quad.bend_rad_per_unit = glm::pi<float>();
    const auto bent = picture_of(folder, "quad.gltf", bent_quad);
    ASSERT_EQ(flat.width, 200u);
    ASSERT_EQ(bent.width, 200u);
    const double ratio = width_of(bent) / width_of(flat);
    EXPECT_GT(width_of(flat), 120.0);
    const double edge = 0.3 / glm::pi<double>();
    EXPECT_NEAR(ratio, (edge / (0.5 - edge)) / (0.15 / 0.5), 0.04) << "flat " << width_of(flat) << " px, bent " << width_of(bent) << " px";
    EXPECT_GT(share_of(bent, {1, 0, 0}, 0, 0, 100, 100), 0.05) << "still red at the top left";
}

namespace {

// A flat disc of radius 0.5 (a polar grid, 8 rings of 32), facing +z: 480 triangles.
assets::MeshData fine_disc() {
    assets::MeshData m;
    m.name = "disc";
    const int rings = 8, around = 32;
    for (int i = 0; i <= rings; ++i) {
        for (int j = 0; j < around; ++j) {
            const float r = 0.5f * static_cast<float>(i) / rings, a = 6.2831853f * static_cast<float>(j) / around;
            m.positions.push_back({r * std::cos(a), r * std::sin(a), 0.0f});
            m.normals.push_back({0, 0, 1});
        }
    }
    const auto at = [](int i, int j) { return static_cast<std::uint32_t>(i * around + (j % around)); };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < around; ++j) {
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            if (i > 0) m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)}); // not at the centre's point
        }
    }
    return m;
}

// How many pixels are not the background.
std::size_t covered(const RgbaImage& img) {
    const glm::vec3 background = DrawList{}.background * 255.0f;
    std::size_t n = 0;
    for (std::size_t k = 0; k + 3 < img.pixels.size(); k += 4) {
        if (glm::distance(glm::vec3(img.pixels[k], img.pixels[k + 1], img.pixels[k + 2]), background) > 20.0f) ++n;
    }
    return n;
}

} // namespace

// Level of detail: discs a few pixels across are drawn from the coarse copy (far fewer triangles) and
// cover what the modelled mesh covers; one large disc is drawn as modelled.
TEST_F(StereoRendererTest, SmallInstancesAreDrawnCoarseAndCoverWhatTheMeshCovers) {
    const auto picture = [](double coarse_below_px, const std::vector<MeshInstance>& instances) {
        auto options = sized(200, 200);
        options.mode = StereoMode::mono;
        options.generated_mesh = [](const std::string& name) { return name == "disc" ? std::optional(fine_disc()) : std::nullopt; };
        options.coarse_below_px = coarse_below_px;
        auto renderer = StereoRenderer::create(*shared_context(), options);
        EXPECT_TRUE(renderer) << renderer.error().message;
        DrawList list;
        list.batch("disc").instances = instances;
        auto frame = (*renderer)->render(list, facing_rig(), false);
        EXPECT_TRUE(frame) << frame.error().message;
        return std::move(frame).value();
    };
    // 5 x 5 discs 24 mm across at 0.5 m: about 13 px each at this eye's 274 px focal length.
    std::vector<MeshInstance> small;
    for (int i = 0; i < 5; ++i) {
        for (int j = 0; j < 5; ++j) small.push_back(facing_quad(0.024f, {-0.12f + 0.06f * static_cast<float>(i), 0.0f, -0.12f + 0.06f * static_cast<float>(j)}));
    }
    const auto modelled = picture(0.0, small), coarse = picture(40.0, small);
    const std::uint64_t per_disc = fine_disc().indices.size() / 3;
    EXPECT_EQ(modelled.timing.eye_triangles, 25 * per_disc);
    EXPECT_LT(coarse.timing.eye_triangles, modelled.timing.eye_triangles / 3) << coarse.timing.eye_triangles << " triangles";
    EXPECT_EQ(coarse.timing.shadow_triangles, coarse.timing.eye_triangles) << "the shadow pass takes the same copies";
    const double a = static_cast<double>(covered(modelled.composed)), b = static_cast<double>(covered(coarse.composed));
    EXPECT_GT(a, 25 * 80.0) << "the discs are drawn";
    EXPECT_NEAR(b / a, 1.0, 0.12) << a << " px modelled, " << b << " px coarse";
    EXPECT_EQ(per_disc, 480u);
    // One disc 0.3 m across (164 px): as modelled.
    const auto large = picture(40.0, {facing_quad(0.3f)});
    EXPECT_EQ(large.timing.eye_triangles, per_disc);
    // Large and small in one batch, the large one listed between small ones: each is drawn where it is
    // and in its own colour (the large ones go first in the instance buffer, the small after them).
    std::vector<MeshInstance> mixed;
    for (int i = 0; i < 5; ++i) {
        auto disc = facing_quad(0.024f, {-0.12f + 0.06f * static_cast<float>(i), 0.0f, -0.12f});
        disc.colour = {0, 1, 0, 1};
        mixed.push_back(disc);
        if (i == 2) {
            auto big = facing_quad(0.12f, {0.0f, 0.0f, 0.06f});
            big.colour = {1, 0, 0, 1};
            mixed.push_back(big);
        }
    }
    const auto both = picture(40.0, mixed);
    EXPECT_EQ(both.timing.eye_triangles, per_disc + (coarse.timing.eye_triangles / 25) * 5) << "one as modelled, five coarse";
    // The big red disc's middle (0.06 m up: 33 px above the centre) and the green row (0.12 m down).
    EXPECT_GT(share_of(both.composed, {1, 0, 0}, 90, 57, 110, 77), 0.9);
    EXPECT_LT(share_of(both.composed, {0, 1, 0}, 90, 57, 110, 77), 0.05);
    EXPECT_GT(share_of(both.composed, {0, 1, 0}, 20, 160, 180, 172), 0.2);
    EXPECT_LT(share_of(both.composed, {1, 0, 0}, 20, 160, 180, 172), 0.01);
}
