#include "engine/render/png_image.hpp"

#include <cstdlib>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include "engine/core/third_party.hpp"
IKEBANA_THIRD_PARTY_BEGIN
#include <stb_image_write.h>
IKEBANA_THIRD_PARTY_END

#include "engine/assets/files.hpp"
#include "engine/assets/image.hpp"

namespace ikebana::render {

Result<std::string> encode_png(const RgbaImage& image, const std::string& label) {
    if (image.width == 0 || image.height == 0 || image.pixels.size() != 4ull * image.width * image.height) {
        return make_error(ErrorCode::invalid_argument, label + ": no image to write");
    }
    std::string bytes;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, static_cast<int>(image.width), static_cast<int>(image.height), 4, image.pixels.data(),
                                static_cast<int>(image.width * 4))) {
        return make_error(ErrorCode::io_error, label + ": cannot be encoded");
    }
    return bytes;
}

Result<void> write_png(const std::filesystem::path& path, const RgbaImage& image) {
    // Encoded in memory and written through the one output door (exclusive temporary, rename).
    auto bytes = encode_png(image, path.string());
    if (!bytes) return std::move(bytes).error();
    return assets::write_file_atomically(path, *bytes);
}

Result<RgbaImage> read_png(const std::filesystem::path& path) {
    auto bytes = assets::read_text_file(path);
    if (!bytes) return std::move(bytes).error();
    auto decoded = assets::decode_image(*bytes, path.string(), 1u << 15);
    if (!decoded) return std::move(decoded).error();
    return RgbaImage{decoded->width, decoded->height, std::move(decoded->pixels)};
}

Result<ImageDifference> compare_images(const RgbaImage& a, const RgbaImage& b, int threshold) {
    if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size()) {
        return make_error(ErrorCode::invalid_argument, "images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " and " +
                                                           std::to_string(b.width) + "x" + std::to_string(b.height));
    }
    ImageDifference d;
    std::size_t over = 0;
    double sum = 0.0;
    for (std::size_t p = 0; p < a.pixels.size(); p += 4) {
        bool big = false;
        for (std::size_t c = 0; c < 3; ++c) {
            const int diff = std::abs(static_cast<int>(a.pixels[p + c]) - static_cast<int>(b.pixels[p + c]));
            sum += diff;
            big = big || diff > threshold;
        }
        over += big ? 1 : 0;
    }
    const double pixels = static_cast<double>(a.pixels.size() / 4);
    d.mean_abs = pixels > 0 ? sum / (3.0 * pixels) : 0.0;
    d.share_over_threshold = pixels > 0 ? static_cast<double>(over) / pixels : 0.0;
    return d;
}

} // namespace ikebana::render
