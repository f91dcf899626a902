#pragma once
// Ray/sphere geometry around the planet centre. Rays are described by the
// start radius r, the cosine mu of their zenith angle and the altitude h = r - R
// (kept separately, because r^2 - R^2 in float32 would lose metres at 6.4e6 m).
#include <algorithm>
#include <cmath>

namespace cr {

// Distance along the ray to the sphere of radius `radius` (outgoing hit), or
// -1 when the ray misses it. r and mu describe the ray start. Computed in double:
// the discriminant cancels catastrophically in float near the horizon.
inline double distance_to_sphere_exit(double r, double mu, double radius) {
  const double disc = r * r * (mu * mu - 1.0) + radius * radius;
  if (disc < 0.0) return -1.0;
  const double t = -r * mu + std::sqrt(disc);
  return t >= 0.0 ? t : -1.0;
}

// Distance to the first hit of the ground sphere from outside/on it, or -1.
inline double distance_to_ground(double r, double mu, double ground_radius) {
  if (mu >= 0.0) return -1.0;
  // On (or under) the ground looking down, the ground is here; computed, the
  // discriminant and t round to either side of 0 and half such rays missed it.
  if (r <= ground_radius) return 0.0;
  const double disc = r * r * (mu * mu - 1.0) + ground_radius * ground_radius;
  if (disc < 0.0) return -1.0;
  const double t = -r * mu - std::sqrt(disc);
  return t >= 0.0 ? t : -1.0;
}

// Cosine of the zenith angle of the horizon seen from radius r (>= R): rays
// with mu below it hit the ground.
inline double horizon_mu(double r, double ground_radius) {
  const double h = std::max(r - ground_radius, 0.0);
  return -std::sqrt(h * (2.0 * ground_radius + h)) / r;
}

// Altitude at distance t along a ray starting at altitude h0 with r0*mu = r0mu.
// r^2 - R^2 = h0 (2R + h0) + t (t + 2 r0 mu): every term is small, so float is exact enough.
inline float altitude_along_ray(float ground_radius, float h0_2r_h0, float r0mu, float t) {
  const float r2_minus_R2 = h0_2r_h0 + t * (t + 2.0f * r0mu);
  const float r2 = ground_radius * ground_radius + r2_minus_R2;
  return r2_minus_R2 / (ground_radius + std::sqrt(r2 < 0.0f ? 0.0f : r2));  // a select, not std::max: it vectorizes
}

}  // namespace cr
