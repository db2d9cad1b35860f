#include "systems/physics/part_attachment.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::systems::physics {

AttachmentFrame attachment_frame(const std::vector<glm::dvec3>& x, std::size_t index) {
    AttachmentFrame f{};
    if (x.empty()) return {glm::dvec3{0.0}, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}};
    const std::size_t i = std::min(index, x.size() - 1);
    f.origin_m = x[i];
    const glm::dvec3 along = i + 1 < x.size() ? x[i + 1] - x[i] : (i > 0 ? x[i] - x[i - 1] : glm::dvec3{0, 0, 1});
    f.up = glm::length(along) > 0.0 ? glm::normalize(along) : glm::dvec3{0, 0, 1};
    f.side = std::abs(f.up.x) < 0.9 ? glm::normalize(glm::cross(f.up, glm::dvec3{1, 0, 0})) : glm::normalize(glm::cross(f.up, glm::dvec3{0, 1, 0}));
    f.third = glm::cross(f.up, f.side);
    return f;
}

glm::dvec3 first_director(glm::dvec3 along) {
    const glm::dvec3 up = glm::length(along) > 0.0 ? glm::normalize(along) : glm::dvec3{0, 0, 1};
    const glm::dvec3 axis = std::abs(up.x) < 0.9 ? glm::dvec3{1, 0, 0} : glm::dvec3{0, 1, 0};
    return glm::normalize(axis - glm::dot(axis, up) * up);
}

AttachmentFrame attachment_frame(const std::vector<glm::dvec3>& x, std::size_t index, const std::vector<glm::dvec3>& directors) {
    AttachmentFrame f = attachment_frame(x, index);
    if (x.size() < 2 || directors.size() + 1 != x.size()) return f;
    const glm::dvec3 d = directors[std::min(index, directors.size() - 1)];
    const glm::dvec3 side = glm::cross(f.up, d);
    if (glm::length(side) < 1e-9) return f;
    f.side = glm::normalize(side);
    f.third = glm::cross(f.up, f.side);
    return f;
}

} // namespace ikebana::systems::physics
