// The knob tables of the image-based model and the hand (pipeline/ibr_settings.h,
// hand_settings.h, config/knobs.h): the command-line options they bind, a site config's "ibr" and
// "hand" objects, and the options a parent forwards to a child. CPU only.
#include <catch2/catch.hpp>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>

#include "app/option_groups.h"
#include "ibr/lumi_net_model.h"
#include "site/site_options.h"

using namespace rt;
using pipeline::HandRendererOptions;
using pipeline::IbrSettings;

namespace {

// Parses `args` (without the program name) with the image-based-model and hand groups.
std::pair<IbrSettings, HandRendererOptions> parse(std::vector<std::string> args, IbrSettings ibr = {},
                                                  HandRendererOptions hand = {}) {
  CLI::App app;
  app::IbrOptions ibr_options = app::add_ibr_options(app);
  app::HandOptions hand_options = app::add_hand_options(app);
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  app.parse(args);
  ibr_options.apply(ibr);
  hand_options.apply(hand);
  return {ibr, hand};
}

}  // namespace

TEST_CASE("the image-based model's options set its settings") {
  const auto [ibr, hand] = parse({"--refine", "9", "--carve", "--fusion", "avg", "--edge-inset", "0.3", "--views", "6",
                                  "--best-views", "5", "--average-tolerance", "0.02", "--portrait-supersample", "2",
                                  "--hand-shape-adaption", "off", "--hand-min-confidence", "0.25"});
  CHECK(ibr.refine);
  CHECK(ibr.refinement.hypotheses == 9);
  CHECK(ibr.carve);
  CHECK(ibr.fusion == passes::DepthFusion::Average);
  CHECK(ibr.splat.edge_inset == 0.3f);
  CHECK(ibr.views == 6);
  CHECK(ibr.blend.best_views == 5);
  CHECK(ibr.splat.average_tolerance_m == 0.02f);
  CHECK(ibr.supersample == 2);
  CHECK_FALSE(hand.shape_adaption);
  CHECK(hand.min_confidence == 0.25f);

  // Options not given keep what the settings had (a config's values, here refine 4).
  IbrSettings from_config;
  from_config.refine = true;
  from_config.refinement.hypotheses = 4;
  const auto [kept, unused] = parse({"--views", "2"}, from_config);
  CHECK(kept.refine);
  CHECK(kept.refinement.hypotheses == 4);
  CHECK(kept.views == 2);
  // --refine 0 is off.
  CHECK_FALSE(parse({"--refine", "0"}, from_config).first.refine);
}

TEST_CASE("the options refuse values out of their range") {
  CHECK_THROWS_AS(parse({"--refine", "65"}), CLI::ValidationError);
  CHECK_THROWS_AS(parse({"--edge-inset", "0.5"}), CLI::ValidationError);
  CHECK_THROWS_AS(parse({"--views", "0"}), CLI::ValidationError);
  CHECK_THROWS_AS(parse({"--fusion", "median"}), CLI::ValidationError);
  CHECK_THROWS_AS(parse({"--hand-shape-adaption", "maybe"}), CLI::ValidationError);
}

TEST_CASE("a config's ibr and hand objects are read, and checked") {
  IbrSettings ibr;
  config::read_knobs_json(pipeline::ibr_knobs(), {{"refine", 9}, {"best_views", 4}, {"carve", true}, {"fusion", "avg"}},
                          ibr, "site.json: 'ibr'");
  CHECK(ibr.refine);
  CHECK(ibr.refinement.hypotheses == 9);
  CHECK(ibr.blend.best_views == 4);
  CHECK(ibr.carve);
  CHECK(ibr.fusion == passes::DepthFusion::Average);

  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"refin", 9}}, ibr, "site.json: 'ibr'"),
                      Catch::Contains("site.json: 'ibr': unknown field 'refin'") && Catch::Contains("refine"));
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"edge_inset", 0.5}}, ibr, "site.json: 'ibr'"),
                      Catch::Contains("'edge_inset' must be a number in [0, 0.49], is 0.5"));
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"refine", 2.5}}, ibr, "site.json: 'ibr'"),
                      Catch::Contains("'refine' must be an integer in [0, 64]"));
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"carve", 1}}, ibr, "site.json: 'ibr'"),
                      Catch::Contains("'carve' must be true or false"));
  HandRendererOptions hand;
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::hand_knobs(), {{"min_confidence", 2}}, hand, "site.json: 'hand'"),
                      Catch::Contains("site.json: 'hand': field 'min_confidence' must be a number in [0, 1], is 2"));

  // Through the site config: the file and the key are named.
  const auto folder = std::filesystem::temp_directory_path() / "remotetouch_test_knobs";
  std::filesystem::create_directories(folder);
  const auto good = folder / "good.json", bad = folder / "bad.json";
  std::ofstream(good) << R"({"scene": "clap", "ibr": {"refine": 9, "views": 6}, "hand": {"shape_adaption": "off"}})";
  std::ofstream(bad) << R"({"ibr": {"views": 4, "no_such_knob": 1}})";
  site::SiteRunOptions options;
  site::apply_site_config(good, options);
  CHECK(options.ibr.refine);
  CHECK(options.ibr.refinement.hypotheses == 9);
  CHECK(options.ibr.views == 6);
  CHECK_FALSE(options.hand.shape_adaption);
  REQUIRE_THROWS_WITH(site::apply_site_config(bad, options),
                      Catch::Contains(bad.string() + ": 'ibr': unknown field 'no_such_knob'"));
}

// Regression (tests/fuzz/corpus/site_config/broken_nested_knob_value.json is its small twin): the
// error for a wrong value dumped the value, recursively, and a site config whose knob held an
// array nested a million deep overflowed the stack instead of being refused.
TEST_CASE("a knob's value nested a million deep is refused, not a stack overflow") {
  const size_t depth = 1'000'000;
  const nlohmann::json object = nlohmann::json::parse("{\"views\": " + std::string(depth, '[') + std::string(depth, ']') + "}");
  IbrSettings ibr;
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), object, ibr, "site.json: 'ibr'"),
                      Catch::Contains("field 'views' must be an integer in [1, 6], is an array"));
  const auto path = std::filesystem::temp_directory_path() / "remotetouch_test_knobs" / "nested.json";
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << R"({"hand": {"min_confidence": )" << std::string(depth, '[') << std::string(depth, ']') << "}}";
  site::SiteRunOptions options;
  REQUIRE_THROWS_WITH(site::apply_site_config(path, options),
                      Catch::Contains("'min_confidence' must be a number in [0, 1], is an array"));
}

TEST_CASE("the options a parent forwards give the child the same settings") {
  IbrSettings ibr;
  ibr.refine = true;
  ibr.refinement.hypotheses = 9;
  ibr.carve = true;
  ibr.fusion = passes::DepthFusion::Average;
  ibr.splat.edge_inset = 0.3f;
  ibr.blend.best_views = 4;
  ibr.split_warp = true;
  HandRendererOptions hand;
  hand.shape_adaption = false;
  hand.appearance_smoothing = 0.4f;
  std::vector<std::string> args = config::knob_arguments(pipeline::ibr_knobs(), ibr, IbrSettings{});
  CHECK(std::find(args.begin(), args.end(), "0.3") != args.end());  // a float as it was written
  for (const auto& arg : config::knob_arguments(pipeline::hand_knobs(), hand, HandRendererOptions{}, pipeline::kHandOptionPrefix))
    args.push_back(arg);
  const auto [child_ibr, child_hand] = parse(args);
  CHECK(pipeline::ibr_settings_json(child_ibr) == pipeline::ibr_settings_json(ibr));
  CHECK(pipeline::hand_settings_json(child_hand) == pipeline::hand_settings_json(hand));
  CHECK(pipeline::ibr_settings_json(child_ibr)["refine"] == 9);
  CHECK(pipeline::ibr_settings_json(child_ibr)["edge_inset"] == 0.3);
  CHECK(child_ibr.split_warp);
  // The defaults forward nothing.
  CHECK(config::knob_arguments(pipeline::ibr_knobs(), IbrSettings{}, IbrSettings{}).empty());
}

TEST_CASE("the blending and Lumi-Net's weights file are knobs like the others") {
  CHECK(IbrSettings{}.blending == pipeline::IbrBlending::Ulr);
  CHECK(pipeline::ibr_settings_json(IbrSettings{})["blend"] == "ulr");
  CHECK(pipeline::ibr_settings_json(IbrSettings{})["lumi_weights"] == ibr::default_lumi_net_path().string());

  const auto [ibr, hand] = parse({"--blend", "lumi", "--lumi-weights", "trained/net.bin"});
  CHECK(ibr.blending == pipeline::IbrBlending::Lumi);
  CHECK(pipeline::lumi_weights_path(ibr) == "trained/net.bin");
  CHECK_THROWS_AS(parse({"--blend", "median"}), CLI::ValidationError);
  CHECK_THROWS_AS(parse({"--lumi-weights", ""}), CLI::ValidationError);

  // Forwarded to a child: both, and only when they differ from the defaults.
  const std::vector<std::string> args = config::knob_arguments(pipeline::ibr_knobs(), ibr, IbrSettings{});
  CHECK(args == std::vector<std::string>{"--blend", "lumi", "--lumi-weights", "trained/net.bin"});
  const auto [child, unused] = parse(args);
  CHECK(pipeline::ibr_settings_json(child) == pipeline::ibr_settings_json(ibr));
  IbrSettings named_default;
  named_default.lumi_weights = ibr::default_lumi_net_path();
  CHECK(config::knob_arguments(pipeline::ibr_knobs(), named_default, IbrSettings{}).empty());

  // A site config's "ibr" object.
  IbrSettings from_json;
  config::read_knobs_json(pipeline::ibr_knobs(), {{"blend", "lumi"}, {"lumi_weights", "w.bin"}}, from_json,
                          "site.json: 'ibr'");
  CHECK(from_json.blending == pipeline::IbrBlending::Lumi);
  CHECK(from_json.lumi_weights == "w.bin");
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"blend", "lumigraph"}}, from_json, "site.json: 'ibr'"),
                      Catch::Contains("'blend' must be one of ulr, lumi"));
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"lumi_weights", 3}}, from_json, "site.json: 'ibr'"),
                      Catch::Contains("'lumi_weights' must be a non-empty string, is 3"));
  REQUIRE_THROWS_WITH(config::read_knobs_json(pipeline::ibr_knobs(), {{"lumi_weights", ""}}, from_json, "site.json: 'ibr'"),
                      Catch::Contains("'lumi_weights' must be a non-empty string"));
}
