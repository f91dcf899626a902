#include "engine/render/composite_strips.h"

#include <algorithm>

namespace cr {

int composite_strip_rows(int height, unsigned threads) {
  const int per_four = height / (4 * int(std::max(threads, 1u)));
  return std::clamp(per_four / 8 * 8, 8, 32);
}

void for_each_composite_strip(JobSystem& jobs, const char* name, int width, int height,
                              const std::function<void(int x0, int y0, int x1, int y1)>& fn) {
  const int rows = composite_strip_rows(height, jobs.thread_count());
  const int strips = (height + rows - 1) / rows;
  jobs.parallel_for(name, size_t(strips), 1, [&](size_t begin, size_t end) {
    for (size_t s = begin; s < end; ++s) {
      const int y0 = int(s) * rows;
      fn(0, y0, width, std::min(height, y0 + rows));
    }
  });
}

}  // namespace cr
