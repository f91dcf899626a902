#pragma once
// Deterministic lattice noise for the scene generator: integer hashing and
// value noise evaluated with +, *, floor only, so the generated scene is
// bit-identical on every run and machine (no libm transcendentals involved).
#include <cstdint>

namespace cr::gen {

// A well-mixed 32-bit hash of a lattice point and a seed.
uint32_t hash2(int32_t x, int32_t y, uint32_t seed);

// Hash mapped to [0, 1).
double hash_unit(int32_t x, int32_t y, uint32_t seed);

// Value noise in [0, 1] with quintic interpolation; lattice spacing 1.
// period > 0 wraps the lattice so the noise tiles with that period.
double value_noise(double x, double y, uint32_t seed, int32_t period = 0);

// Fractal sum of value noise, normalised to [0, 1]: octave i has frequency
// 2^i and weight gain^i. period (of octave 0) tiles every octave.
double fbm(double x, double y, uint32_t seed, int octaves, double gain = 0.5, int32_t period = 0);

// Ridged fractal noise in [0, 1]: sharp crests where the noise crosses 0.5,
// which reads as mountain ridges; each octave is weighted by the previous
// ridge so detail gathers on the crests.
double ridged_fbm(double x, double y, uint32_t seed, int octaves);

double smoothstep(double edge0, double edge1, double x);

}  // namespace cr::gen
