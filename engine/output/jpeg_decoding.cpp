#include <cstdio>  // jpeglib.h needs FILE and size_t declared first

#include <jpeglib.h>
#include <jerror.h>

#include <csetjmp>

#include "engine/output/image_decoding.h"

namespace cr {

namespace {

// Each progressive scan walks every coefficient again: a few kilobytes of
// scans can take minutes. libjpeg-turbo's own tools stop at 500.
constexpr int kMaxScans = 500;

struct JpegErrors {
  jpeg_error_mgr mgr;
  jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_error(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  longjmp(e->jump, 1);
}
// Warnings (e.g. extraneous bytes) are not errors, but data that ends early
// is: libjpeg would fill the rest with grey, so 1.4 KB could decode to a
// 11536x15121 image (a fuzzer finding: tests/data/bad/fuzz_image_jpeg_truncated_huge.jpg).
void on_message(j_common_ptr cinfo, int level) {
  if (level < 0 && cinfo->err->msg_code == JWRN_JPEG_EOF) {
    auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
    std::snprintf(e->message, sizeof e->message, "JPEG data is truncated");
    longjmp(e->jump, 1);
  }
}

void on_progress(j_common_ptr cinfo) {
  auto* d = reinterpret_cast<j_decompress_ptr>(cinfo);
  if (d->input_scan_number > kMaxScans) {
    auto* e = reinterpret_cast<JpegErrors*>(cinfo->err);
    std::snprintf(e->message, sizeof e->message, "JPEG has more than %d progressive scans", kMaxScans);
    longjmp(e->jump, 1);
  }
}

// Only trivially destructible locals live across setjmp, so the longjmp skips
// no destructor; `out` is sized between the header and the scanlines.
bool read_jpeg(const uint8_t* bytes, size_t size, int max_edge, DecodedImage& out, JpegErrors& err) {
  jpeg_decompress_struct cinfo;
  jpeg_progress_mgr progress;
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = on_error;
  err.mgr.emit_message = on_message;
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  progress.progress_monitor = on_progress;
  cinfo.progress = &progress;
  jpeg_mem_src(&cinfo, bytes, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.image_width > JDIMENSION(max_edge) || cinfo.image_height > JDIMENSION(max_edge)) {
    std::snprintf(err.message, sizeof err.message, "JPEG size %ux%u is outside 1..%d per edge", cinfo.image_width,
                  cinfo.image_height, max_edge);
    longjmp(err.jump, 1);
  }
  // Progressive files buffer every coefficient (2 bytes each, up to four
  // components): beyond that libjpeg reports an error instead of allocating.
  cinfo.mem->max_memory_to_use = long(size_t(cinfo.image_width) * cinfo.image_height * 12 + (size_t(64) << 20));
  const bool cmyk = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
  cinfo.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  cinfo.dct_method = JDCT_ISLOW;
  jpeg_start_decompress(&cinfo);
  const size_t w = cinfo.output_width, h = cinfo.output_height;
  out.width = int(w);
  out.height = int(h);
  out.file_channels = cinfo.jpeg_color_space == JCS_GRAYSCALE ? 1 : 3;
  // Reserved, then grown row by row: pages are touched only as rows decode,
  // so data that ends early is refused before the whole image is paid for.
  out.rgba.reserve(w * h * 4);
  while (cinfo.output_scanline < cinfo.output_height) {
    out.rgba.resize(out.rgba.size() + w * 4);
    JSAMPROW row = out.rgba.data() + size_t(cinfo.output_scanline) * w * 4;
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  const bool adobe_inverted = cinfo.saw_Adobe_marker;
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  if (cmyk) {
    // Adobe writes CMYK inverted (255 = no ink): RGB = (255 - C) (255 - K) / 255 otherwise.
    for (size_t i = 0; i < w * h; ++i) {
      uint8_t* p = &out.rgba[4 * i];
      uint32_t k = p[3];
      uint32_t c[3] = {p[0], p[1], p[2]};
      if (!adobe_inverted) {
        k = 255 - k;
        for (uint32_t& v : c) v = 255 - v;
      }
      for (int j = 0; j < 3; ++j) p[j] = uint8_t((c[j] * k + 127) / 255);
      p[3] = 255;
    }
  }
  return true;
}

}  // namespace

bool decode_jpeg(const uint8_t* bytes, size_t size, int max_edge, DecodedImage& out, std::string& error) {
  if (size < 3 || bytes[0] != 0xFF || bytes[1] != 0xD8) {
    error = "not a JPEG file";
    return false;
  }
  JpegErrors err{};
  if (read_jpeg(bytes, size, max_edge, out, err)) return true;
  out = DecodedImage{};
  error = err.message;
  return false;
}

}  // namespace cr
