#include "engine/render/png_image.hpp"

#include <cstdlib>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#include <stb_image.h>
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "engine/assets/files.hpp"

namespace ikebana::render {

Result<void> write_png(const std::filesystem::path& path, const RgbaImage& image) {
    if (image.width == 0 || image.height == 0 || image.pixels.size() != 4ull * image.width * image.height) {
        return make_error(ErrorCode::invalid_argument, path.string() + ": no image to write");
    }
    // Encoded in memory and written through the one output door (exclusive temporary, rename).
    std::string bytes;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &bytes, static_cast<int>(image.width), static_cast<int>(image.height), 4, image.pixels.data(),
                                static_cast<int>(image.width * 4))) {
        return make_error(ErrorCode::io_error, path.string() + ": cannot be encoded");
    }
    return assets::write_file_atomically(path, bytes);
}

Result<RgbaImage> read_png(const std::filesystem::path& path) {
    auto bytes = assets::read_text_file(path);
    if (!bytes) return std::move(bytes).error();
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes->data()), static_cast<int>(bytes->size()), &w, &h, &channels, 4);
    if (!data) return make_error(ErrorCode::parse_error, path.string() + ": not a readable PNG (" + stbi_failure_reason() + ")");
    RgbaImage img;
    img.width = static_cast<std::uint32_t>(w);
    img.height = static_cast<std::uint32_t>(h);
    img.pixels.assign(data, data + 4ull * img.width * img.height);
    stbi_image_free(data);
    return img;
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
