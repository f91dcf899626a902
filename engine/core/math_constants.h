#pragma once
// π, defined once for the whole project: glm's value, as float and as double.
// kPi is the float nearest π (the literal 3.14159265358979f rounds to the
// same float) and kPiD the double nearest π (the value of POSIX's M_PI);
// tests/core/test_math_constants.cpp checks both, bit for bit.
#include <glm/gtc/constants.hpp>

namespace cr {

inline constexpr float kPi = glm::pi<float>();
inline constexpr double kPiD = glm::pi<double>();

}  // namespace cr
