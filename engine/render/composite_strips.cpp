#include "engine/render/composite_strips.h"

#include <algorithm>

namespace cr {

void for_each_composite_strip(JobSystem& jobs, const char* name, int width, int height,
                              const std::function<void(int x0, int y0, int x1, int y1)>& fn) {
  const int strips = (height + kCompositeStripRows - 1) / kCompositeStripRows;
  jobs.parallel_for(name, size_t(strips), 1, [&](size_t begin, size_t end) {
    for (size_t s = begin; s < end; ++s) {
      const int y0 = int(s) * kCompositeStripRows;
      fn(0, y0, width, std::min(height, y0 + kCompositeStripRows));
    }
  });
}

}  // namespace cr
