#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>

#include "engine/output/image_decoding.h"

namespace cr {

namespace {

struct PngSource {
  const uint8_t* bytes;
  size_t size;
  size_t offset;
  char message[160];
};

void read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* src = static_cast<PngSource*>(png_get_io_ptr(png));
  if (n > src->size - src->offset) png_error(png, "PNG data is truncated");
  std::memcpy(out, src->bytes + src->offset, n);
  src->offset += n;
}

// libpng reports through longjmp: keep its message for the caller.
void on_error(png_structp png, png_const_charp message) {
  auto* src = static_cast<PngSource*>(png_get_error_ptr(png));
  std::snprintf(src->message, sizeof src->message, "%s", message);
  png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}

// Reads the header and, once `out` is sized, the rows. Only trivially
// destructible locals live across setjmp, so the longjmp skips no destructor.
bool read_png(PngSource& src, int max_edge, DecodedImage& out) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, on_error, on_warning);
  if (!png) {
    std::snprintf(src.message, sizeof src.message, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  png_bytep* volatile rows = nullptr;  // set after setjmp: volatile keeps it valid after a longjmp
  if (!info || setjmp(png_jmpbuf(png))) {
    delete[] rows;
    png_destroy_read_struct(&png, &info, nullptr);
    if (!src.message[0]) std::snprintf(src.message, sizeof src.message, "out of memory");
    return false;
  }
  png_set_read_fn(png, &src, read_bytes);
  png_set_user_limits(png, png_uint_32(max_edge), png_uint_32(max_edge));
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  const int bit_depth = png_get_bit_depth(png, info), color = png_get_color_type(png, info);
  const bool alpha = (color & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS);
  out.file_channels = (color & PNG_COLOR_MASK_COLOR) ? (alpha ? 4 : 3) : (alpha ? 2 : 1);
  png_set_expand(png);  // palette to RGB, grey below 8 bits to 8 bits, tRNS to alpha
  if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if (!alpha) png_set_add_alpha(png, bit_depth == 16 ? 0xFFFF : 0xFF, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  if (row_bytes != size_t(w) * (bit_depth == 16 ? 8 : 4)) png_error(png, "PNG has an unexpected pixel layout");
  out.width = int(w);
  out.height = int(h);
  // 16-bit rows are read into the output's storage at twice its size and
  // rounded down to 8 bits in place afterwards.
  out.rgba.assign(row_bytes * h, 0);
  rows = new png_bytep[h];
  for (png_uint_32 y = 0; y < h; ++y) rows[y] = out.rgba.data() + size_t(y) * row_bytes;
  png_read_image(png, rows);
  png_read_end(png, nullptr);
  delete[] rows;
  rows = nullptr;
  png_destroy_read_struct(&png, &info, nullptr);
  if (bit_depth == 16) {
    const size_t n = size_t(w) * h * 4;
    for (size_t i = 0; i < n; ++i) {
      const uint32_t v = (uint32_t(out.rgba[2 * i]) << 8) | out.rgba[2 * i + 1];  // PNG is big-endian
      out.rgba[i] = uint8_t((v * 255u + 32767u) / 65535u);
    }
    out.rgba.resize(n);
    out.rgba.shrink_to_fit();
  }
  return true;
}

}  // namespace

bool decode_png(const uint8_t* bytes, size_t size, int max_edge, DecodedImage& out, std::string& error) {
  if (size < 8 || png_sig_cmp(bytes, 0, 8) != 0) {
    error = "not a PNG file";
    return false;
  }
  // The size, from IHDR, is checked here for a message libpng does not give
  // ("Invalid IHDR data"); libpng checks it again through its user limits.
  if (size >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
    auto be32 = [&](size_t at) {
      return (uint32_t(bytes[at]) << 24) | (uint32_t(bytes[at + 1]) << 16) | (uint32_t(bytes[at + 2]) << 8) | bytes[at + 3];
    };
    const uint32_t w = be32(16), h = be32(20);
    if (w == 0 || h == 0 || w > uint32_t(max_edge) || h > uint32_t(max_edge)) {
      error = "PNG size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." + std::to_string(max_edge) +
              " per edge";
      return false;
    }
  }
  PngSource src{bytes, size, 0, {}};
  if (read_png(src, max_edge, out)) return true;
  out = DecodedImage{};
  error = src.message;
  return false;
}

}  // namespace cr
