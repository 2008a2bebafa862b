// The configurations, results and choices of `bench accuracy` (pipeline/accuracy_grid.h,
// accuracy_results.h, quality.h): every grid expands to distinct configurations, the fronts are
// the rows no other beats, results.csv reads back what was written, and --budget-ms and the
// presets choose what they say. CPU only.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "pipeline/accuracy_grid.h"
#include "pipeline/accuracy_results.h"
#include "pipeline/quality.h"

using namespace rt;
using namespace rt::pipeline;

namespace {

AccuracyRow row(const std::string& options, double psnr_fg, double psnr_hand, double ms) {
  AccuracyRow r;
  r.options = options;
  r.ibr.width = 96;
  r.ibr.height = 54;
  r.resolution_scale = 0.5;
  r.scenes = "wave";
  r.frames = 2;
  r.psnr_fg_db = psnr_fg;
  r.psnr_hand_db = psnr_hand;
  r.gpu_ms = r.gpu_ms_q1 = r.gpu_ms_q3 = ms;
  return r;
}

}  // namespace

TEST_CASE("every grid expands to distinct configurations, the defaults first") {
  for (const AccuracyGrid& grid : accuracy_grids()) {
    const std::vector<AccuracyConfig> configs = expand_grid(grid);
    REQUIRE(configs.size() > 1);
    CHECK(accuracy_options(configs.front(), 640, 360).empty());
    std::vector<std::string> names;
    for (const AccuracyConfig& config : configs) names.push_back(accuracy_options(config, 640, 360));
    std::sort(names.begin(), names.end());
    CHECK(std::adjacent_find(names.begin(), names.end()) == names.end());
  }
  // The test's grid: the defaults, each of its knobs alone, and the one product point not among them.
  CHECK(expand_grid(accuracy_grid("tiny")).size() == 7);
  // small: each knob alone (the defaults among them), and the product's points with two or more knobs set.
  CHECK(expand_grid(accuracy_grid("small")).size() == 17);
  // full: Lumi-Net's blend is one of its axes, named by its option.
  bool lumi = false;
  for (const AccuracyConfig& config : expand_grid(accuracy_grid("full")))
    lumi = lumi || accuracy_options(config, 640, 360) == "--blend lumi";
  CHECK(lumi);
}

TEST_CASE("a configuration is named by the options that set it") {
  AccuracyConfig config;
  set_axis(config, "views", "6");
  set_axis(config, "carve", "on");
  set_axis(config, "resolution-scale", "1");
  set_axis(config, "portrait-scale", "0.5");
  CHECK(accuracy_options(config, 640, 360) == "--views 6 --carve --resolution-scale 1 --width 320 --height 180");
  set_axis(config, "resolution-scale", "scene");
  set_axis(config, "carve", "off");
  CHECK(accuracy_options(config, 640, 360) == "--views 6 --width 320 --height 180");
  CHECK(portrait_size(config, 20, 20) == std::pair<uint32_t, uint32_t>(16, 16));
}

TEST_CASE("a bad grid axis or value is an error naming it") {
  AccuracyConfig config;
  CHECK_THROWS_WITH(set_axis(config, "sharpness", "1"), Catch::Contains("unknown grid axis 'sharpness'") &&
                                                            Catch::Contains("views"));
  CHECK_THROWS_WITH(set_axis(config, "views", "9"), Catch::Contains("'9' is not an integer in [1, 6]"));
  CHECK_THROWS_WITH(set_axis(config, "fusion", "median"), Catch::Contains("one of min, avg"));
  CHECK_THROWS_WITH(set_axis(config, "carve", "yes"), Catch::Contains("not on or off"));
  CHECK_THROWS_WITH(set_axis(config, "resolution-scale", "2"), Catch::Contains("not in (0, 1]"));
  CHECK_THROWS_WITH(accuracy_grid("huge"), Catch::Contains("unknown grid 'huge' (known: tiny, small, full)"));
}

TEST_CASE("the fronts hold the rows that no other beats in both accuracy and time") {
  std::vector<AccuracyRow> rows = {row("a", 20, 15, 10), row("b", 22, 14, 20), row("c", 21, 16, 30),
                                   row("d", 22, 13, 20), row("e", 19, 17, 10)};
  mark_fronts(rows);
  // c is slower and less accurate than b; d ties b in both (neither beats the other).
  CHECK(rows[0].on_front);
  CHECK(rows[1].on_front);
  CHECK_FALSE(rows[2].on_front);
  CHECK(rows[3].on_front);
  CHECK_FALSE(rows[4].on_front);
  // The hand: e is as fast as a and better; c is the only one better than e.
  CHECK_FALSE(rows[0].on_front_hand);
  CHECK_FALSE(rows[1].on_front_hand);
  CHECK_FALSE(rows[3].on_front_hand);
  CHECK(rows[4].on_front_hand);
  CHECK_FALSE(rows[2].on_front_hand);
}

TEST_CASE("results.csv reads back what was written, and --budget-ms picks from it") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rt_test_accuracy_results";
  std::filesystem::create_directories(dir);
  std::vector<AccuracyRow> rows = {row("", 20, 15, 10), row("--views 6 --refine 9", 23, 16, 40),
                                   row("--fusion avg --carve", 21.5, 15.5, 12)};
  rows[1].ibr.views = 6;
  rows[1].ibr.refine = true;
  rows[1].ibr.refinement.hypotheses = 9;
  rows[1].resolution_scale = 1;
  rows[2].ibr.fusion = passes::DepthFusion::Average;
  rows[2].ibr.carve = true;
  mark_fronts(rows);
  write_accuracy_csv(dir / "results.csv", rows);
  const std::vector<AccuracyRow> read = read_accuracy_csv(dir / "results.csv");
  REQUIRE(read.size() == 3);
  CHECK(read[1].options == "--views 6 --refine 9");
  CHECK(read[1].ibr.views == 6);
  CHECK(read[1].ibr.refinement.hypotheses == 9);
  CHECK(read[2].ibr.fusion == passes::DepthFusion::Average);
  CHECK(read[2].ibr.carve);
  CHECK(read[1].psnr_fg_db == Approx(23));

  CHECK(most_accurate_within(read, 15, 96, 54, "test").options == "--fusion avg --carve");
  CHECK(most_accurate_within(read, 100, 96, 54, "test").options == "--views 6 --refine 9");
  CHECK_THROWS_WITH(most_accurate_within(read, 5, 96, 54, "test"),
                    Catch::Contains("nothing measured at 96x54 fits 5 GPU ms") && Catch::Contains("the defaults"));
  CHECK_THROWS_WITH(most_accurate_within(read, 100, 640, 360, "test"),
                    Catch::Contains("no configuration measured at 640x360 (measured: 96x54)"));

  IbrSettings base;
  base.width = 96;
  base.height = 54;
  const QualityChoice choice = quality_within_budget(dir / "results.csv", 100, base);
  CHECK(choice.ibr.views == 6);
  CHECK(choice.resolution_scale == 1);
  CHECK(choice.description["options"] == "--views 6 --refine 9");

  // A file of other columns is refused, naming it.
  std::ofstream(dir / "other.csv") << "a,b\n1,2\n";
  CHECK_THROWS_WITH(read_accuracy_csv(dir / "other.csv"), Catch::Contains("other.csv: line 1: not the columns"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("the presets are fast, balanced and best, and each is a valid setting") {
  const std::vector<std::string> names = quality_preset_names();
  CHECK(names == std::vector<std::string>{"balanced", "best", "fast"});
  for (const std::string& name : names) {
    const QualityChoice choice = quality_preset(name, IbrSettings{});
    CHECK(choice.description["preset"] == name);
  }
  CHECK_THROWS_WITH(quality_preset("ultra", IbrSettings{}), Catch::Contains("no preset 'ultra' (known: balanced, best, fast)"));
}
