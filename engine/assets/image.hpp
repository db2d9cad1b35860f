#pragma once
// Pictures a mesh's materials name (PNG or JPEG, as Blender exports them), decoded with stb_image into
// 8-bit RGBA. The size is read from the header first, so a small file claiming a huge picture is
// refused before anything is allocated.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::assets {

struct DecodedImage {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::vector<std::uint8_t> pixels; // row 0 at the top, 4 bytes per pixel (RGBA)
};

// A flower's texture needs no more: 4096 x 4096 is 64 MiB of pixels.
inline constexpr std::uint32_t max_image_side = 4096;

// `label` names the picture in errors ("tulip.gltf: /images/0").
Result<DecodedImage> decode_image(std::string_view bytes, const std::string& label, std::uint32_t max_side = max_image_side);

} // namespace ikebana::assets
