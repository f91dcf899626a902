#include "engine/shading/texel_decode.h"

namespace cr {

const std::array<float, 256>& unorm_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i) / 255.0f;
    return t;
  }();
  return table;
}

}  // namespace cr
