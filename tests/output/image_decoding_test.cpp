// PNG and JPEG decoding of untrusted bytes (libpng, libjpeg-turbo): exact
// round trips of PNGs written by an independent encoder (stb_image_write),
// 16-bit channels rounded to 8 bits, JPEG within its quantisation error, and
// every truncation of a valid file an error message, never a crash.
#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/output/image_decoding.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace {

void append(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

std::vector<uint8_t> pattern(int w, int h, int channels) {
  std::vector<uint8_t> p(size_t(w) * h * channels);
  for (size_t i = 0; i < p.size(); ++i) p[i] = uint8_t((i * 37u + i / 7u) & 0xFF);
  return p;
}

uint32_t crc32(const uint8_t* p, size_t n, uint32_t crc = 0xFFFFFFFFu) {
  for (size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc;
}

void put32(std::vector<uint8_t>& v, uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(uint8_t(x >> s));
}

void chunk(std::vector<uint8_t>& png, const char* type, const std::vector<uint8_t>& data) {
  put32(png, uint32_t(data.size()));
  std::vector<uint8_t> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  png.insert(png.end(), body.begin(), body.end());
  put32(png, crc32(body.data(), body.size()) ^ 0xFFFFFFFFu);
}

// A 16-bit RGBA PNG, written by hand: zlib stream of stored blocks.
std::vector<uint8_t> png16(int w, int h, const std::vector<uint16_t>& rgba) {
  std::vector<uint8_t> raw;
  for (int y = 0; y < h; ++y) {
    raw.push_back(0);  // filter: none
    for (int x = 0; x < w * 4; ++x) {
      raw.push_back(uint8_t(rgba[size_t(y) * w * 4 + x] >> 8));
      raw.push_back(uint8_t(rgba[size_t(y) * w * 4 + x]));
    }
  }
  std::vector<uint8_t> z = {0x78, 0x01};
  for (size_t off = 0; off < raw.size(); off += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - off);
    z.push_back(off + n == raw.size() ? 1 : 0);
    z.push_back(uint8_t(n));
    z.push_back(uint8_t(n >> 8));
    z.push_back(uint8_t(~n));
    z.push_back(uint8_t(~n >> 8));
    z.insert(z.end(), raw.begin() + long(off), raw.begin() + long(off + n));
  }
  uint32_t a = 1, b = 0;
  for (uint8_t c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  put32(z, (b << 16) | a);
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<uint8_t> ihdr;
  put32(ihdr, uint32_t(w));
  put32(ihdr, uint32_t(h));
  ihdr.insert(ihdr.end(), {16, 6, 0, 0, 0});  // 16-bit RGBA, deflate, no filter variants, no interlace
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", z);
  chunk(png, "IEND", {});
  return png;
}

}  // namespace

TEST_CASE("image decoding: PNGs of 1-4 channels from an independent encoder decode exactly to RGBA8") {
  const int w = 37, h = 23;
  for (int channels = 1; channels <= 4; ++channels) {
    const std::vector<uint8_t> src = pattern(w, h, channels);
    std::vector<uint8_t> png;
    REQUIRE(stbi_write_png_to_func(append, &png, w, h, channels, src.data(), w * channels));
    cr::DecodedImage img;
    std::string error;
    REQUIRE(cr::decode_png(png.data(), png.size(), 16384, img, error));
    CHECK(img.width == w);
    CHECK(img.height == h);
    CHECK(img.file_channels == channels);
    REQUIRE(img.rgba.size() == size_t(w) * h * 4);
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      const uint8_t* s = &src[i * channels];
      const uint8_t* d = &img.rgba[i * 4];
      const bool grey = channels <= 2;
      for (int c = 0; c < 3; ++c) REQUIRE(d[c] == (grey ? s[0] : s[c]));
      REQUIRE(d[3] == (channels == 2 ? s[1] : channels == 4 ? s[3] : 255));
    }
  }
}

TEST_CASE("image decoding: 16-bit PNG channels round to the nearest 8-bit code") {
  const int w = 64, h = 4;
  std::vector<uint16_t> rgba(size_t(w) * h * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint16_t((i * 4099u) & 0xFFFF);
  const std::vector<uint8_t> png = png16(w, h, rgba);
  cr::DecodedImage img;
  std::string error;
  REQUIRE(cr::decode_png(png.data(), png.size(), 16384, img, error));
  REQUIRE(img.rgba.size() == rgba.size());
  for (size_t i = 0; i < rgba.size(); ++i) REQUIRE(img.rgba[i] == uint8_t((rgba[i] * 255u + 32767u) / 65535u));
}

TEST_CASE("image decoding: a JPEG decodes within its quantisation error, and sizes over the limit are refused") {
  const int w = 48, h = 32;
  std::vector<uint8_t> src(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) src[(size_t(y) * w + x) * 3 + c] = uint8_t(40 + 3 * x + 2 * y + 30 * c);
  std::vector<uint8_t> jpg;
  REQUIRE(stbi_write_jpg_to_func(append, &jpg, w, h, 3, src.data(), 100));
  cr::DecodedImage img;
  std::string error;
  REQUIRE(cr::decode_jpeg(jpg.data(), jpg.size(), 16384, img, error));
  CHECK(img.width == w);
  CHECK(img.height == h);
  int worst = 0;
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(img.rgba[i * 4 + c]) - int(src[i * 3 + c])));
  CHECK(worst <= 8);
  CHECK(!cr::decode_jpeg(jpg.data(), jpg.size(), 40, img, error));
  CHECK(error == "JPEG size 48x32 is outside 1..40 per edge");
  std::vector<uint8_t> png;
  REQUIRE(stbi_write_png_to_func(append, &png, w, h, 3, src.data(), w * 3));
  CHECK(!cr::decode_png(png.data(), png.size(), 40, img, error));
  CHECK(error == "PNG size 48x32 is outside 1..40 per edge");
}

TEST_CASE("image decoding: every truncation and a flipped byte of valid files fail with a message or decode, never crash") {
  const int w = 16, h = 16;
  const std::vector<uint8_t> src = pattern(w, h, 3);
  std::vector<uint8_t> png, jpg;
  REQUIRE(stbi_write_png_to_func(append, &png, w, h, 3, src.data(), w * 3));
  REQUIRE(stbi_write_jpg_to_func(append, &jpg, w, h, 3, src.data(), 90));
  for (size_t n = 0; n < png.size(); ++n) {
    cr::DecodedImage img;
    std::string error;
    CHECK_FALSE(cr::decode_png(png.data(), n, 16384, img, error));
    CHECK(!error.empty());
    CHECK(img.rgba.empty());
  }
  for (size_t n = 0; n < jpg.size(); ++n) {
    cr::DecodedImage img;
    std::string error;
    // libjpeg would fill a cut-off scan with grey: refused instead.
    CHECK_FALSE(cr::decode_jpeg(jpg.data(), n, 16384, img, error));
    CHECK(!error.empty());
    CHECK(img.rgba.empty());
  }
  for (size_t i = 0; i < jpg.size(); ++i) {
    std::vector<uint8_t> bad = jpg;
    bad[i] ^= 0x5A;
    cr::DecodedImage img;
    std::string error;
    if (cr::decode_jpeg(bad.data(), bad.size(), 16384, img, error)) CHECK(img.rgba.size() == size_t(img.width) * img.height * 4);
    else CHECK(!error.empty());
  }
}
