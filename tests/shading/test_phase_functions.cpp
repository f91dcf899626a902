// The shared phase functions: the constants the fog once spelled out are the
// ones computed here bit for bit, and both evaluation orders are the same
// functions up to rounding.
#include <cmath>

#include <doctest/doctest.h>

#include "engine/shading/phase_functions.h"

using namespace cr;

// The fog's former kInvFourPi and kThreeOverEightPi.
static_assert(kIsotropicPhase == 0.07957747154594767f);
static_assert(3.0f / (8.0f * kPi) == 0.11936620731892151f);

TEST_CASE("phase functions: both evaluation orders agree to rounding, float to double") {
  for (float g : {-0.5f, 0.0f, 0.3f, 0.76f, 0.9f}) {
    for (int i = 0; i <= 200; ++i) {
      const float c = -1.0f + float(i) / 100.0f;
      const float hg = henyey_greenstein(c, g), cs = cornette_shanks(c, g);
      CHECK(henyey_greenstein_normalized_first(c, g) == doctest::Approx(hg).epsilon(1e-6));
      CHECK(cornette_shanks_normalized_first(c, g) == doctest::Approx(cs).epsilon(1e-6));
      CHECK(double(hg) == doctest::Approx(henyey_greenstein<double>(c, g)).epsilon(1e-5));
      CHECK(double(cs) == doctest::Approx(cornette_shanks<double>(c, g)).epsilon(1e-5));
    }
  }
  CHECK(henyey_greenstein(0.3f, 0.0f) == kIsotropicPhase);
  CHECK(rayleigh_phase(0.0f) == doctest::Approx(3.0 / (16.0 * kPiD)));
}
