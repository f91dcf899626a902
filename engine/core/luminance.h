#pragma once
// Relative luminance of linear RGB with Rec. 709 (sRGB) primaries: the Y row
// of ITU-R BT.709, rounded to four digits as everywhere in the project.
#include <glm/glm.hpp>

namespace cr {

inline float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace cr
