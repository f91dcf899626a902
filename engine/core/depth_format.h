#pragma once
// How the visibility buffer stores depth (profile "precision": {"depth": ...}).
// Depth is reversed-Z with an infinite far plane (1 at the near plane, 0 at
// infinity); each sample's interpolated depth is rounded to the format before
// the depth test and the store, so surfaces closer than one step of the
// format tie (z-fighting: the first drawn stays).
//   float32  IEEE single: relative precision 2^-24 at every distance.
//   unorm24  24-bit unsigned normalised (steps of 2^-24): with reversed-Z the
//            steps are uniform in 1/distance, so a step spans
//            2^-24 * distance^2 / near metres: about 540 m at 30 km with a
//            0.1 m near plane.
//   float24  a 24-bit float (8-bit exponent, 16-bit mantissa: single
//            precision rounded to nearest in its last 7 bits): reversed-Z
//            float depth is close to logarithmic, a step is about 2^-17 of the
//            distance (0.2 m at 30 km).
namespace cr {

enum class DepthFormat { Float32, Unorm24, Float24 };

}  // namespace cr
