#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/error.h"
#include "engine/output/atomic_file.h"
#include "engine/output/exr_io.h"
#include "engine/output/image_compare.h"
#include "engine/output/png_io.h"
#include "tests/output/scratch_dir.h"

using cr::test::ScratchDir;

namespace {

// A smooth 8-bit test image with structure, values on exact 1/255 codes in [20, 230].
cr::ImageRGBf pattern(int width, int height) {
  cr::ImageRGBf image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      p[0] = static_cast<float>(20 + (x * 210) / (width - 1)) / 255.0f;
      p[1] = static_cast<float>(20 + (y * 210) / (height - 1)) / 255.0f;
      p[2] = static_cast<float>(((x / 4 + y / 4) % 2) ? 200 : 60) / 255.0f;
    }
  return image;
}

bool has_failure(const cr::CompareResult& result, const std::string& metric) {
  for (const std::string& failure : result.failures)
    if (failure.find(metric) == 0) return true;
  return false;
}

void check_input_error(const std::string& reference, const std::string& test,
                       const std::string& blamed) {
  try {
    cr::compare_image_files(reference, test, cr::CompareThresholds{});
    FAIL("expected cr::InputError blaming " << blamed);
  } catch (const cr::InputError& e) {
    CHECK(e.file() == blamed);
  }
}

}  // namespace

TEST_CASE("identical images pass with PSNR inf and FLIP 0") {
  const cr::ImageRGBf image = pattern(32, 24);
  const cr::CompareResult result =
      cr::compare_images(image, image, cr::ImageEncoding::Display, cr::CompareThresholds{});
  CHECK(result.pass);
  CHECK(result.failures.empty());
  CHECK(result.metrics.max_abs == 0.0);
  CHECK(result.metrics.rmse == 0.0);
  CHECK(std::isinf(result.metrics.psnr_db));
  CHECK(result.metrics.psnr_db > 0);
  CHECK(cr::format_psnr(result.metrics.psnr_db) == "inf");
  CHECK(result.metrics.flip_mean == 0.0);
  CHECK(cr::compare_result_to_json(result, {})["metrics"]["psnr_db"] == "inf");
}

TEST_CASE("metrics equal hand-computed values on a 2x2 image") {
  cr::ImageRGBf reference(2, 2), test(2, 2);
  for (float& v : reference.rgb) v = 0.5f;
  test = reference;
  test.pixel(1, 0)[0] = 0.625f;  // R +0.125
  test.pixel(0, 1)[2] = 0.25f;   // B -0.25
  cr::CompareThresholds thresholds;
  thresholds.pixel_threshold = 0.2;
  const cr::CompareMetrics m =
      cr::compare_images(reference, test, cr::ImageEncoding::Display, thresholds).metrics;
  CHECK(m.max_abs_channel[0] == 0.125);
  CHECK(m.max_abs_channel[1] == 0.0);
  CHECK(m.max_abs_channel[2] == 0.25);
  CHECK(m.max_abs == 0.25);
  // MSE = (0.125^2 + 0.25^2) / 12 values
  CHECK(m.rmse == doctest::Approx(std::sqrt(0.078125 / 12.0)));
  CHECK(m.psnr_db == doctest::Approx(10.0 * std::log10(12.0 / 0.078125)));  // 21.864 dB
  CHECK(m.pixels_over == 1);  // only the 0.25 pixel exceeds 0.2
  CHECK(m.fraction_over == 0.25);
}

TEST_CASE("a one-pixel large change fails the max-abs and fraction thresholds") {
  const cr::ImageRGBf reference = pattern(16, 16);
  cr::ImageRGBf test = reference;
  float* p = test.pixel(5, 7);
  p[0] = p[1] = p[2] = 1.0f;
  const cr::CompareResult result =
      cr::compare_images(reference, test, cr::ImageEncoding::Display, cr::CompareThresholds{});
  CHECK_FALSE(result.pass);
  CHECK(has_failure(result, "max abs difference"));
  CHECK(has_failure(result, "fraction of differing pixels"));
  CHECK(result.metrics.pixels_over == 1);
  // The FLIP map localises the change.
  const auto peak = std::max_element(result.flip_map.begin(), result.flip_map.end());
  CHECK(peak - result.flip_map.begin() == 7 * 16 + 5);
  CHECK(*peak > 0.3f);
  CHECK(result.flip_map[0] < 0.01f);
}

TEST_CASE("a global offset of one 8-bit code passes the default thresholds") {
  const cr::ImageRGBf reference = pattern(64, 48);
  cr::ImageRGBf test = reference;
  for (float& v : test.rgb) v += 1.0f / 255.0f;
  const cr::CompareResult result =
      cr::compare_images(reference, test, cr::ImageEncoding::Display, cr::CompareThresholds{});
  INFO(cr::format_compare_result(result, {}));
  CHECK(result.pass);
  CHECK(result.metrics.max_abs == doctest::Approx(1.0 / 255.0).epsilon(1e-4));
  CHECK(result.metrics.pixels_over == 0);
  CHECK(result.metrics.flip_mean > 0.0);
}

TEST_CASE("NaN in the test image always fails") {
  const cr::ImageRGBf reference = pattern(8, 8);
  cr::ImageRGBf test = reference;
  test.pixel(3, 3)[1] = std::numeric_limits<float>::quiet_NaN();
  const cr::CompareResult result =
      cr::compare_images(reference, test, cr::ImageEncoding::Linear, cr::CompareThresholds{});
  CHECK_FALSE(result.pass);
  CHECK(std::isinf(result.metrics.max_abs));
}

TEST_CASE("comparing PNG files, with a heat map of the difference") {
  ScratchDir dir("compare-png");
  const cr::ImageRGBf image = pattern(16, 16);
  cr::ImageRGBf changed = image;
  changed.pixel(9, 4)[0] = 0.0f;
  cr::write_png(dir.file("a.png"), cr::to_rgb8(image));
  cr::write_png(dir.file("b.png"), cr::to_rgb8(changed));

  CHECK(cr::compare_image_files(dir.file("a.png"), dir.file("a.png"), {}).pass);
  const cr::CompareResult result = cr::compare_image_files(dir.file("a.png"), dir.file("b.png"), {});
  CHECK_FALSE(result.pass);
  CHECK(result.metrics.max_abs == doctest::Approx(image.pixel(9, 4)[0]).epsilon(1e-6));

  for (auto kind : {cr::HeatmapKind::Flip, cr::HeatmapKind::Difference}) {
    cr::write_error_heatmap(dir.file("diff.png"), result, kind);
    const cr::Image8 heat = cr::read_png(dir.file("diff.png"));
    CHECK(heat.width == 16);
    CHECK(heat.height == 16);
    CHECK(heat.channels == 3);
    auto brightness = [&](int x, int y) {
      const uint8_t* p = &heat.data[(static_cast<size_t>(y) * 16 + x) * 3];
      return p[0] + p[1] + p[2];
    };
    CHECK(brightness(9, 4) > brightness(0, 15) + 100);
  }
}

TEST_CASE("comparing EXR files uses linear values and a stated tonemap for FLIP") {
  ScratchDir dir("compare-exr");
  cr::ExrImage a;
  a.color = pattern(12, 10);
  for (float& v : a.color.rgb) v *= 4.0f;  // HDR values above 1
  cr::ExrImage b = a;
  b.color.pixel(2, 2)[0] += 2.0f;
  cr::write_exr(dir.file("a.exr"), a);
  cr::write_exr(dir.file("b.exr"), b);
  const cr::CompareResult same = cr::compare_image_files(dir.file("a.exr"), dir.file("a.exr"), {});
  CHECK(same.pass);
  CHECK(same.metrics.encoding == cr::ImageEncoding::Linear);
  CHECK(same.metrics.flip_method.find("ACES") != std::string::npos);
  const cr::CompareResult different =
      cr::compare_image_files(dir.file("a.exr"), dir.file("b.exr"), {});
  CHECK_FALSE(different.pass);
  CHECK(different.metrics.max_abs == doctest::Approx(2.0).epsilon(2e-3));  // half precision
}

TEST_CASE("bad compare inputs are InputErrors naming the file") {
  ScratchDir dir("compare-bad");
  cr::write_png(dir.file("good.png"), cr::to_rgb8(pattern(16, 16)));
  cr::write_png(dir.file("small.png"), cr::to_rgb8(pattern(8, 16)));
  const std::string good = cr::read_file_bytes(dir.file("good.png"));
  cr::write_file_atomic(dir.file("truncated.png"), good.substr(0, good.size() / 2));
  cr::write_file_atomic(dir.file("text.png"), "hello\n");
  cr::write_file_atomic(dir.file("empty.png"), "");
  cr::ExrImage exr;
  exr.color = pattern(16, 16);
  cr::write_exr(dir.file("good.exr"), exr);
  cr::write_exr_channels(dir.file("rg.exr"), 16, 16,
                         {{"R", cr::ExrPixelType::Half, std::vector<float>(256)},
                          {"G", cr::ExrPixelType::Half, std::vector<float>(256)}});

  const std::string reference = dir.file("good.png");
  check_input_error(reference, dir.file("truncated.png"), dir.file("truncated.png"));
  check_input_error(reference, dir.file("text.png"), dir.file("text.png"));
  check_input_error(reference, dir.file("empty.png"), dir.file("empty.png"));
  check_input_error(reference, dir.file("missing.png"), dir.file("missing.png"));
  check_input_error(dir.file("empty.png"), reference, dir.file("empty.png"));
  check_input_error(reference, dir.file("small.png"), dir.file("small.png"));
  check_input_error(reference, dir.file("good.exr"), dir.file("good.exr"));
  check_input_error(dir.file("good.exr"), dir.file("rg.exr"), dir.file("rg.exr"));
}

TEST_CASE("relative luminance error: 0 for identical images, the scale factor for a scaled linear image") {
  cr::ImageRGBf reference(20, 10), test(20, 10);
  for (size_t i = 0; i < reference.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) reference.rgb[i * 3 + c] = 0.5f + 0.1f * float(i % 7) + 0.05f * float(c);
  const cr::CompareThresholds thresholds;
  CHECK(cr::compare_images(reference, reference, cr::ImageEncoding::Linear, thresholds).metrics.rel_luminance_p95 == 0.0);
  for (size_t i = 0; i < test.rgb.size(); ++i) test.rgb[i] = reference.rgb[i] * 1.1f;
  // 10% brighter in 190 pixels, ten pixels 3x: p95 sees the 10%, the mean both.
  for (size_t i = 0; i < 10; ++i)
    for (int c = 0; c < 3; ++c) test.rgb[i * 3 + c] = reference.rgb[i * 3 + c] * 3.0f;
  const cr::CompareMetrics m = cr::compare_images(reference, test, cr::ImageEncoding::Linear, thresholds).metrics;
  CHECK(m.rel_luminance_p95 == doctest::Approx(0.1).epsilon(1e-4));
  CHECK(m.rel_luminance_mean == doctest::Approx((190 * 0.1 + 10 * 2.0) / 200.0).epsilon(1e-4));
}
