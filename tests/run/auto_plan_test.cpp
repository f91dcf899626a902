// `--profile auto`: the planner's choice among measured options (the cheapest
// combination whose errors fit the budget, else the most accurate), what it
// skips and what the scene decides, its table's validation, and the CLI end
// to end. Tables here are written by the tests, so the assertions do not
// depend on the shipped table's measured numbers.
#include <doctest/doctest.h>

#include <fstream>

#include "engine/cli/cli_common.h"
#include "engine/cli/commands.h"
#include "engine/core/error.h"
#include "engine/core/json_input.h"
#include "engine/output/atomic_file.h"
#include "engine/planning/auto_plan.h"
#include "engine/planning/scene_facts.h"
#include "engine/render/plugin_registry.h"
#include "tests/output/scratch_dir.h"

namespace {

std::string scene_path(const std::string& name) { return std::string(CR_BINARY_DIR) + "/scenes/" + name + ".json"; }
std::string desktop() { return std::string(CR_SOURCE_DIR) + "/profiles/desktop.json"; }

// engine: A (10 ms, 1.5%) or B (20 ms, 0.5%); atmosphere: one option
// (2 ms moving, 0.1 ms still, 0.1%); fog: X (1 ms, 1%) or Y (3 ms, 0.2%).
nlohmann::json synthetic_table() {
  auto option = [](const char* name, nlohmann::json settings, double cost, double error) {
    return nlohmann::json{{"name", name}, {"settings", settings}, {"cost_ms", cost}, {"error", error}};
  };
  nlohmann::json atmosphere = option("only", {{"atmosphere.spectral_samples", 3}}, 2.0, 0.001);
  atmosphere["static_cost_ms"] = 0.1;
  return {{"format", "cpurender-auto-table"},
          {"measured", {{"resolution", {1280, 720}}, {"threads", 2}}},
          {"modules",
           {{"engine",
             {{"scales_with_pixels", true},
              {"options",
               {option("A", {{"antialiasing", "none"}}, 10.0, 0.015), option("B", {{"antialiasing", "msaa4"}}, 20.0, 0.005)}}}},
            {"atmosphere", {{"options", {atmosphere}}}},
            {"fog",
             {{"scales_with_pixels", true},
              {"options", {option("X", {{"fog.froxel_size_px", 16}}, 1.0, 0.01), option("Y", {{"fog.froxel_size_px", 8}}, 3.0, 0.002)}}}}}}};
}

struct Planned {
  cr::RunSetup setup;
  cr::AutoPlan plan;
};

Planned plan_for(const std::string& scene, double budget, const nlohmann::json& table_doc, int w = 1280, int h = 720,
                 int frames = 0) {
  cr::test::ScratchDir dir("auto-plan");
  const std::string table_path = dir.file("table.json");
  cr::write_file_atomic(table_path, table_doc.dump());
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  cr::RunRequest request;
  request.frames = frames;
  Planned p{cr::load_run(scene, desktop(), registry, w, h, 1, {}, 0, request), {}};
  p.plan = cr::plan_auto_profile(*p.setup.scene, p.setup.description, cr::load_json_file(desktop()), p.setup.profile,
                                 cr::load_plan_table(table_path), registry.create_all(), budget, p.setup.frames, w, h);
  return p;
}

const cr::ModulePlan& module(const cr::AutoPlan& plan, const std::string& name) {
  for (const cr::ModulePlan& m : plan.modules)
    if (m.module == name) return m;
  FAIL("no module " << name);
  return plan.modules.front();
}

std::string chosen(const cr::AutoPlan& plan, const std::string& name) {
  for (size_t i = 0; i < plan.modules.size(); ++i)
    if (plan.modules[i].module == name)
      return plan.chosen[i] < 0 ? "off" : plan.modules[i].options[size_t(plan.chosen[i])].name;
  return "?";
}

}  // namespace

TEST_CASE("auto plan: the cheapest options whose errors sum within the budget, else the most accurate") {
  const nlohmann::json table = synthetic_table();
  // Fog scene: A+X is 2.6% (over 2%); A+Y is 1.8% at 10 + 2 + 3 ms, cheaper than B+X (2 + 20 + 1).
  Planned p = plan_for(scene_path("fog_valley_flythrough"), 0.02, table);
  CHECK(chosen(p.plan, "engine") == "A");
  CHECK(chosen(p.plan, "fog") == "Y");
  CHECK(p.plan.meets_error_budget);
  CHECK(p.plan.predicted_ms == doctest::Approx(15.0));
  CHECK(p.plan.predicted_error == doctest::Approx(0.018));
  CHECK(p.plan.profile["antialiasing"] == "none");
  CHECK(p.plan.profile["fog"]["froxel_size_px"] == 8);
  CHECK(p.plan.profile["name"] == "auto");
  // A looser budget takes the cheapest of all; a tighter one pays for accuracy.
  CHECK(chosen(plan_for(scene_path("fog_valley_flythrough"), 0.03, table).plan, "fog") == "X");
  Planned tight = plan_for(scene_path("fog_valley_flythrough"), 0.009, table);
  CHECK(chosen(tight.plan, "engine") == "B");
  CHECK(chosen(tight.plan, "fog") == "Y");
  // Nothing fits 0.1%: the most accurate combination, said so.
  Planned none = plan_for(scene_path("fog_valley_flythrough"), 0.001, table);
  CHECK_FALSE(none.plan.meets_error_budget);
  CHECK(chosen(none.plan, "engine") == "B");
  CHECK(none.plan.summary().find("no setting in the table meets the error budget") != std::string::npos);
  // The predicted cost is over 33.3 ms only when it is: B+Y = 25 ms fits the frame budget.
  CHECK(none.plan.meets_frame_budget);
}

TEST_CASE("auto plan: what the scene does not use costs nothing, still scenes pay LUTs once, costs scale with pixels") {
  const nlohmann::json table = synthetic_table();
  // No fog section: no fog passes, and the engine's cheap option now fits alone (1.5% + 0.1%).
  Planned sky = plan_for(scene_path("sky_earth_noon"), 0.02, table);
  CHECK_FALSE(module(sky.plan, "fog").used);
  CHECK(module(sky.plan, "fog").note.find("no fog section") != std::string::npos);
  CHECK(chosen(sky.plan, "engine") == "A");
  // Camera and sun hold still: the atmosphere's LUTs are built once (its still cost).
  CHECK(sky.plan.facts.camera_static());
  CHECK(sky.plan.facts.sun_static());
  CHECK(sky.plan.predicted_ms == doctest::Approx(10.0 + 0.1));
  // No atmosphere section: no sky passes.
  CHECK_FALSE(module(plan_for(scene_path("engine_only"), 0.02, table).plan, "atmosphere").used);
  // Half the pixels each way: a quarter of the engine's cost, the LUTs' unchanged.
  Planned small = plan_for(scene_path("sky_earth_noon"), 0.02, table, 640, 360);
  CHECK(small.plan.predicted_ms == doctest::Approx(2.5 + 0.1));
}

TEST_CASE("auto plan: a view that geometry barely covers keeps render scale 1") {
  nlohmann::json table = synthetic_table();
  // A third engine option, the cheapest: half the resolution.
  table["modules"]["engine"]["options"].push_back(
      {{"name", "half"}, {"settings", {{"antialiasing", "none"}, {"render_scale", 0.5}}}, {"cost_ms", 4.0}, {"error", 0.005}});
  // The village from inside it: the bounds fill the view, and the scale is the cheapest fit.
  const Planned village = plan_for(scene_path("default"), 0.02, table);
  CHECK(village.plan.facts.max_geometry_coverage == 1.0);
  CHECK(chosen(village.plan, "engine") == "half");
  // From orbit the village is a speck: no scaled option, and the plan says why.
  const Planned orbit = plan_for(scene_path("sky_orbit"), 0.02, table);
  CHECK(orbit.plan.facts.max_geometry_coverage < 0.01);
  CHECK(chosen(orbit.plan, "engine") != "half");
  const cr::ModulePlan& engine = module(orbit.plan, "engine");
  CHECK(engine.options.size() == 2);
  REQUIRE_FALSE(engine.settings.empty());
  CHECK(engine.settings.back().key == "render_scale");
  CHECK(engine.settings.back().reason.find("geometry covers at most") != std::string::npos);
  CHECK(orbit.plan.profile["render_scale"] == 1.0);
}

TEST_CASE("auto plan: geometry coverage is the projected bounds' share of the view") {
  cr::Scene scene;
  scene.draws.push_back({});  // geometry whose bounds are a 2 m cube at the origin
  scene.bounds_min = glm::vec3(-1.0f);
  scene.bounds_max = glm::vec3(1.0f);
  cr::SceneDescription d;
  cr::CameraKey key;
  key.vfov_deg = 90.0f;
  key.target = {0, 0, 0};
  for (double distance : {3.0, 5.0, 9.0}) {
    key.position = {0, 0, distance};
    d.camera.keys = {key};
    // A square view at 90 degrees: the cube's near face, distance - 1 away,
    // spans 2 / (distance - 1) of each axis's 2 NDC units.
    const double side = 1.0 / (distance - 1.0);
    CHECK(cr::analyse_scene(scene, d, 1, 100, 100).max_geometry_coverage == doctest::Approx(side * side).epsilon(1e-4));
  }
  key.position = {0, 0, 0.5};  // inside the bounds: corners behind the camera
  d.camera.keys = {key};
  CHECK(cr::analyse_scene(scene, d, 1, 100, 100).max_geometry_coverage == 1.0);
}

TEST_CASE("auto plan: an option's error is the largest measured on table scenes of the planned scene's kind") {
  nlohmann::json table = synthetic_table();
  // X: 0.2% on still day scenes, 1% (its "error") elsewhere.
  table["modules"]["fog"]["options"][0]["errors"] = {
      {{"scene", "a"}, {"moving", false}, {"twilight", false}, {"error", 0.002}},
      {{"scene", "b"}, {"moving", true}, {"twilight", false}, {"error", 0.01}}};
  // fog_volumes holds camera and sun still by day: A + X fits (1.5% + 0.2%) and is cheaper than A + Y.
  Planned still = plan_for(scene_path("fog_volumes"), 0.02, table, 320, 180);
  REQUIRE_FALSE(still.plan.facts.moving());
  CHECK_FALSE(still.plan.facts.twilight());
  CHECK(chosen(still.plan, "fog") == "X");
  CHECK(still.plan.predicted_error == doctest::Approx(0.017));
  // The flythrough moves: X is 1% there, and A + Y it stays.
  CHECK(chosen(plan_for(scene_path("fog_valley_flythrough"), 0.02, table, 320, 180).plan, "fog") == "Y");
  // No table scene of the kind (a still twilight scene): the largest over all, 1%.
  table["modules"]["fog"]["options"][0]["errors"][1]["moving"] = false;
  table["modules"]["fog"]["options"][0]["errors"][1]["twilight"] = true;
  CHECK(chosen(plan_for(scene_path("fog_valley_flythrough"), 0.02, table, 320, 180).plan, "fog") == "Y");
}

TEST_CASE("auto plan: the scene decides the aerial-perspective range, twilight steps and the shadow distance") {
  const nlohmann::json table = synthetic_table();
  Planned p = plan_for(scene_path("fog_valley_flythrough"), 0.02, table);
  const cr::SceneFacts& f = p.plan.facts;
  CHECK(f.max_camera_speed_m > 0.0);
  CHECK(f.has_geometry);
  // The slices end past the farthest geometry, and nearer than the base's range.
  const double per_slice = p.plan.profile["atmosphere"]["aerial_perspective_lut"]["km_per_slice"].get<double>();
  const double depth = p.plan.profile["atmosphere"]["aerial_perspective_lut"]["depth"].get<double>();
  CHECK(per_slice * depth * 1000.0 >= f.max_geometry_distance_m);
  CHECK(per_slice < 4.0);
  // The sunset reaches -4 degrees: more sky-view steps. Noon does not.
  Planned sunset = plan_for(scene_path("sky_sunset_timelapse"), 0.02, table, 320, 180);
  CHECK(sunset.plan.facts.min_sun_elevation_deg < 0.0);
  CHECK(sunset.plan.profile["atmosphere"]["skyview_lut"]["max_steps"] == 32);
  CHECK(sunset.plan.facts.max_sun_turn_deg > 0.0);
  Planned noon = plan_for(scene_path("sky_earth_noon"), 0.02, table, 320, 180);
  CHECK(noon.plan.profile["atmosphere"]["skyview_lut"]["max_steps"] == 14);
  // The plan is a function of its inputs.
  CHECK(plan_for(scene_path("fog_valley_flythrough"), 0.02, table).plan.to_json() == p.plan.to_json());
}

TEST_CASE("auto plan: a fog section with nothing to scatter in adds no fog passes") {
  cr::test::ScratchDir dir("auto-plan-empty-fog");
  nlohmann::json scene = cr::load_json_file(scene_path("sky_earth_noon"));
  scene["gltf"] = std::string(CR_BINARY_DIR) + "/scenes/default.glb";
  scene["fog"] = nlohmann::json::object();
  const std::string path = dir.file("empty_fog.json");
  cr::write_file_atomic(path, scene.dump());
  Planned p = plan_for(path, 0.02, synthetic_table(), 160, 90);
  CHECK_FALSE(module(p.plan, "fog").used);
  CHECK(module(p.plan, "fog").note.find("neither height fog nor volumes") != std::string::npos);
  // And the renderer agrees: no fog pass runs.
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::vector<std::string> args = {path, "--profile", desktop(), "--resolution", "64x36", "--threads", "1",
                                         "--format", "none", "--no-trace", "--quiet", "--out", dir.file("out")};
  REQUIRE(cr::render_command(args, registry) == 0);
  const nlohmann::json report = cr::load_json_file(dir.file("out/report.json"));
  for (const nlohmann::json& pass : report["summary"]["passes"]) CHECK(pass["name"].get<std::string>().rfind("fog.", 0) != 0);
}

TEST_CASE("auto plan table: malformed tables are refused naming the file and field") {
  cr::test::ScratchDir dir("auto-plan-table");
  auto refusal = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json t = synthetic_table();
    edit(t);
    const std::string path = dir.file("t.json");
    cr::write_file_atomic(path, t.dump());
    try {
      (void)cr::load_plan_table(path);
    } catch (const cr::InputError& e) {
      CHECK(e.file() == path);
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(refusal([](nlohmann::json&) {}).empty());
  CHECK(refusal([](nlohmann::json& t) { t["format"] = "x"; }).find("format") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["modules"].erase("engine"); }).find("engine") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["modules"]["fog"]["options"][0]["cost_ms"] = -1; })
            .find("modules.fog.options[0].cost_ms") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["modules"]["fog"]["options"] = nlohmann::json::array(); })
            .find("modules.fog.options") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["modules"]["fog"]["speed"] = 1; }).find("unknown key 'speed'") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["modules"]["fog"]["options"][1]["errors"] = {{{"scene", "s"}}}; })
            .find("modules.fog.options[1].errors[0]") != std::string::npos);
  CHECK(refusal([](nlohmann::json& t) { t["measured"]["resolution"] = "big"; }).find("measured.resolution") !=
        std::string::npos);
}

TEST_CASE("auto plan: the shipped table plans every shipped scene into a valid profile") {
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  for (const char* name : {"default", "default_flythrough", "engine_only", "fog_valley_flythrough", "fog_valley_sunrise",
                           "fog_volumes", "sky_earth_noon", "sky_hazy_morning", "sky_mars", "sky_orbit",
                           "sky_sunset_timelapse"}) {
    CAPTURE(name);
    cr::RunRequest request;
    request.plan_table = std::string(CR_SOURCE_DIR) + "/profiles/planner/auto_table.json";
    const cr::RunSetup s = cr::load_run(scene_path(name), "auto:" + desktop(), registry, 160, 90, 1, {}, 0, request);
    REQUIRE(s.plan);
    CHECK(s.profile.name == "auto");
    CHECK(s.plan->predicted_error > 0.0);
    for (size_t i = 0; i < s.plan->modules.size(); ++i) CHECK((s.plan->chosen[i] >= 0) == s.plan->modules[i].used);
  }
}

TEST_CASE("render --profile auto: the plan is printed and in report.json, and --error-budget is checked") {
  cr::test::ScratchDir dir("auto-plan-render");
  cr::PluginRegistry registry;
  cr::register_builtin_plugins(registry);
  const std::string table = dir.file("table.json");
  cr::write_file_atomic(table, synthetic_table().dump());
  const std::vector<std::string> args = {scene_path("fog_valley_flythrough"), "--profile", "auto:" + desktop(), "--plan-table", table,
                                         "--error-budget", "0.02", "--resolution", "64x36", "--frames", "2",
                                         "--threads", "2", "--format", "none", "--no-trace", "--quiet",
                                         "--out", dir.file("out")};
  REQUIRE(cr::render_command(args, registry) == 0);
  const nlohmann::json report = cr::load_json_file(dir.file("out/report.json"));
  const nlohmann::json& plan = report["extra"]["plan"];
  CHECK(plan["error_budget"] == 0.02);
  CHECK(plan["meets_error_budget"] == true);
  CHECK(plan["facts"]["frames"] == 2);
  bool fog_choice = false;
  for (const nlohmann::json& c : plan["choices"])
    fog_choice |= c["key"] == "fog.froxel_size_px" && c["value"] == 8 && !c["reason"].get<std::string>().empty();
  CHECK(fog_choice);
  std::vector<std::string> bad = args;
  bad[6] = "2";  // --error-budget 2: not a fraction
  CHECK_THROWS_AS(cr::render_command(bad, registry), cr::UsageError);
}
