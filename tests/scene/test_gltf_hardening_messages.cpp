// Inputs whose message used to mislead (issue 22, item 5): a 0-byte image was
// "missing", a truncated PNG an "Unknown image format", and a GLB whose JSON
// chunk length is wrong blamed its BIN chunk. Each now gets an exact message
// naming the file.
#include <chrono>
#include <string>

#include <doctest/doctest.h>

#include "engine/core/error.h"
#include "engine/scene/gltf_loader.h"
#include "tests/scene/gltf_rejection.h"

TEST_CASE("a 0-byte image file is empty, not missing, even when missing images are allowed") {
  const std::string path = cr::test::bad_input("empty_image.gltf");
  const std::string expected = path + ": cannot decode 1 image(s): image 0 'empty_image.png': the file is empty (0 bytes)";
  CHECK(cr::test::gltf_rejection(path) == expected);
  cr::GltfLoadOptions allow;
  allow.allow_missing_images = true;
  CHECK(cr::test::gltf_rejection(path, allow) == expected);
}

TEST_CASE("a PNG cut inside its data is truncated or corrupt, naming the image and its URI") {
  const std::string path = cr::test::bad_input("truncated_png.gltf");
  CHECK(cr::test::gltf_rejection(path) ==
        path + ": image 0 'truncated_png.png': truncated or corrupt PNG data (its header gives 64x64, but the data "
               "does not decode: PNG data is truncated)");
}

// Inputs the fuzzer found crashing or exhausting stb_image 2.27 (Debian's),
// the decoder before libpng and libjpeg-turbo: each is now a clear refusal.
TEST_CASE("fuzz findings: a JPEG Huffman table of more than 256 codes and PNG IDAT lengths past the data are refused") {
  const std::string dht = cr::test::bad_input("fuzz_image_jpeg_dht_overflow.gltf");
  const std::string dht_msg = cr::test::gltf_rejection(dht);
  CHECK(dht_msg.find(dht + ": image 0") == 0);
  CHECK(dht_msg.find("truncated or corrupt JPEG data") != std::string::npos);
  for (const char* name : {"fuzz_image_png_idat_length_past_end.gltf", "fuzz_image_png_empty_idat_memcpy_null.gltf"}) {
    const std::string path = cr::test::bad_input(name);
    const std::string msg = cr::test::gltf_rejection(path);
    INFO(msg);
    CHECK(msg.find(path + ": image 0") == 0);
    CHECK(msg.find("truncated or corrupt PNG data") != std::string::npos);
  }
}

TEST_CASE("a GLB whose JSON chunk length is wrong blames the JSON chunk, not the BIN chunk") {
  SUBCASE("shorter than the JSON text (432 bytes)") {
    const std::string path = cr::test::bad_input("glb_json_chunk_short.glb");
    CHECK(cr::test::gltf_rejection(path) == path + ": GLB JSON chunk length is wrong: its 392 bytes end at byte 412, where neither "
                                    "the file ends nor a BIN chunk header starts");
  }
  SUBCASE("4 bytes too long, into the BIN chunk header") {
    const std::string path = cr::test::bad_input("glb_json_chunk_into_bin_header.glb");
    CHECK(cr::test::gltf_rejection(path) == path + ": GLB JSON chunk length is wrong: its 436 bytes end at byte 456, where neither "
                                    "the file ends nor a BIN chunk header starts");
  }
}

// Found by fuzz_image in a 10-minute run: 1.4 KB of JPEG whose frame header
// says 11536x15121 and whose data ends at once; libjpeg filled the rest with
// grey, so decoding and mipmapping took over a minute. Refusing it takes about
// 3 s in a release build and 6-7 s under ASan on a busy 2-core machine: the
// bound is well below the fault's minute and well above those.
TEST_CASE("fuzz findings: a JPEG whose data ends early is refused as truncated, before the image is decoded") {
  const std::string path = cr::test::bad_input("fuzz_image_jpeg_truncated_huge.gltf");
  const auto t0 = std::chrono::steady_clock::now();
  const std::string msg = cr::test::gltf_rejection(path);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(msg == path + ": image 0: truncated or corrupt JPEG data (its header gives 11536x15121, but the data does not "
                      "decode: JPEG data is truncated)");
  CHECK(s < 20.0);
}
