#include "engine/assets/image.hpp"

// The program's one copy of stb_image (png_image.cpp reads PNGs through it): PNG and JPEG only, the
// formats glTF allows.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#include "engine/core/third_party.hpp"
IKEBANA_THIRD_PARTY_BEGIN
#include <stb_image.h>
IKEBANA_THIRD_PARTY_END

#include <climits>
#include <memory>

namespace ikebana::assets {

Result<DecodedImage> decode_image(std::string_view bytes, const std::string& label, std::uint32_t max_side) {
    if (bytes.empty() || bytes.size() > static_cast<std::size_t>(INT_MAX)) {
        return make_error(ErrorCode::parse_error, label + ": " + (bytes.empty() ? "an empty picture" : "a picture larger than 2 GiB"));
    }
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = static_cast<int>(bytes.size());
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(data, size, &w, &h, &channels)) {
        return make_error(ErrorCode::parse_error, label + ": not a PNG or JPEG picture (" + stbi_failure_reason() + ")");
    }
    if (w <= 0 || h <= 0 || static_cast<std::uint32_t>(w) > max_side || static_cast<std::uint32_t>(h) > max_side) {
        return make_error(ErrorCode::parse_error, label + ": a picture of " + std::to_string(w) + "x" + std::to_string(h) +
                                                      " pixels, more than the " + std::to_string(max_side) + " a side that is read");
    }
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(data, size, &w, &h, &channels, 4), stbi_image_free);
    if (!pixels) return make_error(ErrorCode::parse_error, label + ": the picture cannot be decoded (" + stbi_failure_reason() + ")");
    DecodedImage image;
    image.width = static_cast<std::uint32_t>(w);
    image.height = static_cast<std::uint32_t>(h);
    image.pixels.assign(pixels.get(), pixels.get() + 4ull * image.width * image.height);
    return image;
}

} // namespace ikebana::assets
