// The shared math constants equal, bit for bit, the values the code spelled
// out before they were shared (so replacing them changed no result).
#include <cmath>

#include <doctest/doctest.h>

#include "engine/core/math_constants.h"

// The float literal shading, the sky and the tests used for pi, and POSIX's M_PI.
static_assert(cr::kPi == 3.14159265358979f);
static_assert(cr::kPiD == 3.14159265358979323846);
static_assert(cr::kPiD == M_PI);
static_assert(float(cr::kPiD) == cr::kPi);

TEST_CASE("pi is the float and the double nearest pi") {
  CHECK(double(cr::kPi) == doctest::Approx(cr::kPiD).epsilon(1e-7));
  CHECK(std::nextafter(cr::kPi, 0.0f) < 3.14159265358979323846);
  CHECK(std::nextafter(cr::kPi, 4.0f) > 3.14159265358979323846);
}
