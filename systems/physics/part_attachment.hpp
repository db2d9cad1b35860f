#pragma once
// Where a part that hangs on a stem point is, and how it is turned: its offset is kept in the frame of
// the stem's direction at that point. The collider update and the renderer's list use the same frame.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace ikebana::systems::physics {

struct AttachmentFrame {
    glm::dvec3 origin_m; // the stem point
    glm::dvec3 up;       // along the stem there
    glm::dvec3 side;
    glm::dvec3 third;    // up x side
    [[nodiscard]] glm::dvec3 place(const glm::dvec3& offset) const { return origin_m + offset.x * side + offset.y * third + offset.z * up; }
};

AttachmentFrame attachment_frame(const std::vector<glm::dvec3>& points, std::size_t index);
// The same turned with the bark: `directors` (components::StemFrame's, one a segment) give the side, so
// a part turns about the stem when the stem is turned. Without them (empty, or not one a segment), as above.
AttachmentFrame attachment_frame(const std::vector<glm::dvec3>& points, std::size_t index, const std::vector<glm::dvec3>& directors);
// The director a frame without twist starts from, so that the bark's frame of an untwisted stem is the
// one above at its bottom: the room's x across the segment (y where the segment is nearly along x).
glm::dvec3 first_director(glm::dvec3 along);

} // namespace ikebana::systems::physics
