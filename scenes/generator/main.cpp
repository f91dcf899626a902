// scene_generator: writes the project's default scene (see default_scene.h
// for its layout) as a deterministic .glb: the same bytes on every run.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "scenes/generator/default_scene.h"
#include "scenes/generator/glb_check.h"
#include "scenes/generator/gltf_builder.h"
#include "scenes/generator/terrain.h"

namespace {

constexpr const char* kUsage =
    "usage: scene_generator --out <path.glb> [--detail N] [--verify]\n"
    "       scene_generator --height <x> <z>\n"
    "  --out PATH     write the default scene (glTF binary) to PATH\n"
    "  --detail N     terrain detail, 1..8 (default 2): about 56k, 145k, 258k, 391k\n"
    "                 triangles for 1, 2, 3, 4\n"
    "  --verify       load the written file back and check it\n"
    "  --height X Z   print the terrain height (m) at world (X, Z), for placing cameras\n";

const std::string kCli = "scene_generator command line";

double parse_number(const std::string& option, const std::string& text) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty()) throw cr::InputError(kCli, option + ": '" + text + "' is not a number");
  return value;
}

struct Options {
  std::string out;
  int detail = 2;
  bool verify = false;
  std::vector<double> height_query;
};

Options parse(int argc, char** argv) {
  Options o;
  const std::vector<std::string> args(argv + 1, argv + argc);
  // The next argument after option args[i] (values never start with "--").
  const auto value = [&](size_t& i, const std::string& option) -> const std::string& {
    if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) throw cr::InputError(kCli, option + " needs a value");
    return args[++i];
  };
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--out") {
      o.out = value(i, a);
    } else if (a == "--detail") {
      const double d = parse_number(a, value(i, a));
      if (d < 1 || d > 8 || d != static_cast<int>(d)) throw cr::InputError(kCli, "--detail must be an integer in 1..8");
      o.detail = static_cast<int>(d);
    } else if (a == "--verify") {
      o.verify = true;
    } else if (a == "--height") {
      o.height_query.push_back(parse_number(a, value(i, a)));
      o.height_query.push_back(parse_number(a, value(i, a)));
    } else {
      throw cr::InputError(kCli, "unknown option '" + a + "'");
    }
  }
  if (o.out.empty() && o.height_query.empty()) throw cr::InputError(kCli, "--out is required");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  try {
    const Options options = parse(argc, argv);
    if (!options.height_query.empty()) {
      std::printf("%.3f\n", cr::gen::terrain_height(options.height_query[0], options.height_query[1]));
      if (options.out.empty()) return 0;
    }
    const auto start = std::chrono::steady_clock::now();
    const tinygltf::Model model = cr::gen::build_default_scene(options.detail);
    cr::gen::write_glb(model, options.out);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("scene_generator: wrote %s (%ju bytes) in %.2f s\n", options.out.c_str(),
                static_cast<uintmax_t>(std::filesystem::file_size(options.out)), seconds);
    if (options.verify) {
      const cr::gen::GlbSummary s = cr::gen::check_glb(options.out);
      std::printf("verify: OK: %zu nodes, %zu meshes, %zu materials, %zu images, %zu triangles drawn\n", s.nodes,
                  s.meshes, s.materials, s.images, s.triangles_drawn);
    }
    return 0;
  } catch (const cr::InputError& e) {
    std::fprintf(stderr, "error: %s\n%s", e.what(), e.file() == kCli ? kUsage : "");
    return 2;
  } catch (const cr::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
