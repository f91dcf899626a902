// HistoryProjection::read: the trilinear history reads, floats eight slices
// at a time where the CPU has AVX2; q15 codes one slice at a time.
#include "fog/history_projection.h"

#include <immintrin.h>

namespace cr {

namespace {

// HistoryProjection::read, eight slices at a time. Per slice the trilinear
// read needs the 2x2 history columns' values at slices z0 and z0 + 1, which
// are adjacent: four 8-byte loads, packed two slices to a register (one per
// 128-bit half) as {c00 z0, c00 z1, c10 z0, c10 z1} and {c01 .., c11 ..}
// (AVX2 gathers measured ~2x slower than scalar loads here). The lerps run
// in lanes with read_slices' float operations in its order (z, then x, then
// y), so both paths give the same bits. A slice at the grid's last slice
// (no z0 + 1) takes read_slices.
using FloatProjection = HistoryProjection<FloatSunTerm>;

__attribute__((target("avx2"))) size_t read_avx2(const FloatProjection& p, const FloatProjection::Scratch& s,
                                                 const float* cur, int n, float* h) {
  const FroxelGrid& hg = *p.grid;
  const int nx = hg.nx(), ny = hg.ny(), nz = hg.nz();
  const __m256i last_x = _mm256_set1_epi32(nx - 1), last_y = _mm256_set1_epi32(ny - 1),
                last_z = _mm256_set1_epi32(nz - 1), one = _mm256_set1_epi32(1), nx_v = _mm256_set1_epi32(nx),
                nz_v = _mm256_set1_epi32(nz);
  size_t rejected = 0;
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256 fx = _mm256_loadu_ps(&s.fx[size_t(k)]), fy = _mm256_loadu_ps(&s.fy[size_t(k)]),
                 fz = _mm256_loadu_ps(&s.fz[size_t(k)]);
    // The coordinates are clamped to [0, last]: truncation is floor.
    const __m256i x0 = _mm256_cvttps_epi32(fx), y0 = _mm256_cvttps_epi32(fy), z0 = _mm256_cvttps_epi32(fz);
    const __m256 ax = _mm256_sub_ps(fx, _mm256_cvtepi32_ps(x0)), ay = _mm256_sub_ps(fy, _mm256_cvtepi32_ps(y0)),
                 az = _mm256_sub_ps(fz, _mm256_cvtepi32_ps(z0));
    const __m256i x1 = _mm256_min_epi32(_mm256_add_epi32(x0, one), last_x),
                  y1 = _mm256_min_epi32(_mm256_add_epi32(y0, one), last_y);
    const __m256i row0 = _mm256_mullo_epi32(y0, nx_v), row1 = _mm256_mullo_epi32(y1, nx_v);
    // Loads start at min(z0, nz - 2), inside the column (a last-slice lane's values are not used).
    const __m256i z_load = _mm256_min_epi32(z0, _mm256_set1_epi32(nz - 2));
    // Each tap's column (c00, c10, c01, c11) and the index its loads start at.
    const __m256i taps[4] = {_mm256_add_epi32(row0, x0), _mm256_add_epi32(row0, x1), _mm256_add_epi32(row1, x0),
                             _mm256_add_epi32(row1, x1)};
    alignas(32) int32_t column[8], at[4][8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(column), taps[0]);
    for (int t = 0; t < 4; ++t)
      _mm256_store_si256(reinterpret_cast<__m256i*>(at[t]),
                         _mm256_add_epi32(_mm256_mullo_epi32(taps[t], nz_v), z_load));
    alignas(32) int32_t lit[8];
    for (int j = 0; j < 8; ++j) lit[j] = p.lit_2x2[size_t(column[j])];
    // History where the point is inside and the 2x2 columns hold z0 + 1;
    // the grid's last slice (z0 + 1 would be the next column) goes scalar.
    const __m256i at_last = _mm256_cmpeq_epi32(z0, last_z);
    const __m256i inside = _mm256_cmpgt_epi32(
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&s.inside[size_t(k)])), _mm256_setzero_si256());
    const __m256i held = _mm256_cmpgt_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(lit)),
                                            _mm256_add_epi32(z0, one));
    const __m256 take = _mm256_castsi256_ps(_mm256_andnot_si256(at_last, _mm256_and_si256(inside, held)));
    const int scalar = _mm256_movemask_ps(_mm256_castsi256_ps(at_last));
    {
      // As read_slices: the history two columns to the right of the first point.
      const int xp = std::min(int(s.fx[size_t(k)]) + 2, nx - 1), yp = int(s.fy[size_t(k)]), zp = int(s.fz[size_t(k)]);
      __builtin_prefetch(p.values + hg.index(xp, yp, zp));
      __builtin_prefetch(p.values + hg.index(xp, std::min(yp + 1, ny - 1), zp));
    }
    // Slice j's taps into half j / 4 of A[j % 4] (c00, c10) and B[j % 4] (c01, c11).
    __m128 lo_a[8], lo_b[8];
    for (int j = 0; j < 8; ++j) {
      const float* v = p.values;
      lo_a[j] = _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(v + at[0][j]))),
                             reinterpret_cast<const __m64*>(v + at[1][j]));
      lo_b[j] = _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(v + at[2][j]))),
                             reinterpret_cast<const __m64*>(v + at[3][j]));
    }
    __m256 l[4];
    for (int j = 0; j < 4; ++j) {
      const __m256 a = _mm256_set_m128(lo_a[j + 4], lo_a[j]), b = _mm256_set_m128(lo_b[j + 4], lo_b[j]);
      const __m256 z_0 = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0));  // c00 c10 c01 c11 at z0
      const __m256 z_1 = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1));  // the same at z0 + 1
      const __m256 az_j = _mm256_permutevar8x32_ps(az, _mm256_setr_epi32(j, j, j, j, j + 4, j + 4, j + 4, j + 4));
      l[j] = _mm256_add_ps(z_0, _mm256_mul_ps(_mm256_sub_ps(z_1, z_0), az_j));
    }
    // Transpose per half: slice j's (c00, c10, c01, c11) -> a register per tap.
    const __m256 t0 = _mm256_unpacklo_ps(l[0], l[1]), t1 = _mm256_unpackhi_ps(l[0], l[1]);
    const __m256 t2 = _mm256_unpacklo_ps(l[2], l[3]), t3 = _mm256_unpackhi_ps(l[2], l[3]);
    const __m256 v00 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)),
                 v10 = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)),
                 v01 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)),
                 v11 = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 v0 = _mm256_add_ps(v00, _mm256_mul_ps(_mm256_sub_ps(v10, v00), ax));
    const __m256 v1 = _mm256_add_ps(v01, _mm256_mul_ps(_mm256_sub_ps(v11, v01), ax));
    const __m256 value = _mm256_add_ps(v0, _mm256_mul_ps(_mm256_sub_ps(v1, v0), ay));
    _mm256_storeu_ps(h + k, _mm256_blendv_ps(_mm256_loadu_ps(cur + k), value, take));
    rejected += size_t(__builtin_popcount(unsigned(~(_mm256_movemask_ps(take) | scalar) & 0xff)));
    for (int m = scalar; m != 0; m &= m - 1) {
      const int j = __builtin_ctz(unsigned(m));
      rejected += p.read_slices(s, cur, k + j, k + j + 1, h);
    }
  }
  return rejected + p.read_slices(s, cur, k, n, h);
}

}  // namespace

template <>
size_t HistoryProjection<FloatSunTerm>::read(const Scratch& s, const float* cur, int n, float* h) const {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2 && grid->nz() >= 2 ? read_avx2(*this, s, cur, n, h) : read_slices(s, cur, 0, n, h);
}

template <>
size_t HistoryProjection<Q15SunTerm>::read(const Scratch& s, const uint16_t* cur, int n, uint16_t* h) const {
  return read_slices(s, cur, 0, n, h);
}

}  // namespace cr
