#pragma once
// RGBA8 images as the renderer reads them back, and PNG files (stb) for `ikebana render` and the
// golden-image tests.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::render {

struct RgbaImage {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<std::uint8_t> pixels; // row 0 at the top, 4 bytes per pixel
};

Result<void> write_png(const std::filesystem::path& path, const RgbaImage& image);
// The PNG file's bytes (for a command that writes its outputs all or none); `label` names it in errors.
Result<std::string> encode_png(const RgbaImage& image, const std::string& label);
Result<RgbaImage> read_png(const std::filesystem::path& path);

// Mean absolute difference per channel (0..255) and the share of pixels differing by more than
// `threshold` in any channel; sizes must match.
struct ImageDifference {
    double mean_abs = 0.0;
    double share_over_threshold = 0.0;
};
Result<ImageDifference> compare_images(const RgbaImage& a, const RgbaImage& b, int threshold = 24);

} // namespace ikebana::render
