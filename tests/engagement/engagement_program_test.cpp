// Engagement on a real CAM program: FreeCAD 0.20's pocket (3 mm step-downs, then 1 mm) and
// outside profile (4 mm step-downs, arcs at the corners) of one part, posted for LinuxCNC
// (tests/engagement/data/freecad_pocket_profile.ngc, made by freecad_pocket_profile.py beside
// it). Every level cuts only its own step-down, and chosen cutter locations on lines and arcs
// agree with the brute-force oracle (engagement_oracle.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/toolpath/gcode_reader.hpp"
#include "engagement/engagement_oracle.hpp"
#include "engagement/engagement_testing.hpp"
#include "source_dir.hpp"

namespace cwe {
namespace {

constexpr double kSpacing = 0.1;

using test::Sample;

TEST(EngagementProgram, FreeCadPocketAndProfileLevelsCutTheirOwnStepDown) {
  const std::string file =
      (test::source_dir() / "tests/engagement/data/freecad_pocket_profile.ngc").string();
  const Toolpath path = read_gcode_file(file);
  // FreeCAD's stock: the part's box grown by 1 mm; its default 5 mm end mill.
  const Aabb block{{-1, -1, -1}, {81, 51, 21}};
  const Cutter cutter = cutter_from_spec("flat:5,30");
  const std::vector<Sample> samples = test::simulate_samples(path, "flat:5,30", block, kSpacing, 0.5);

  // Horizontal cutter locations by operation (the profile starts at line 156) and tip height.
  std::map<std::pair<bool, double>, double> deepest;
  std::map<std::pair<bool, double>, int> count;
  for (const Sample& s : samples) {
    if (s.state.motion != MotionClass::kHorizontal) continue;
    const std::pair<bool, double> level{s.cl.line >= 156, std::round(s.cl.position.z() * 1e3) / 1e3};
    deepest[level] = std::max(deepest[level], s.map.axial_depth);
    ++count[level];
  }
  // Stock top at 21: pocket levels at 18, 15, 12 and 11; profile levels every 4 mm to -1.
  const std::map<std::pair<bool, double>, double> step_down{
      {{false, 18}, 3}, {{false, 15}, 3}, {{false, 12}, 3}, {{false, 11}, 1},
      {{true, 17}, 4},  {{true, 13}, 4},  {{true, 9}, 4},   {{true, 5}, 4},
      {{true, 1}, 4},   {{true, -1}, 2}};
  ASSERT_EQ(deepest.size(), step_down.size());
  for (const auto& [level, depth] : step_down) {
    SCOPED_TRACE(testing::Message() << (level.first ? "profile" : "pocket") << " at Z"
                                    << level.second);
    EXPECT_GT(count[level], 300);
    EXPECT_NEAR(deepest[level], depth, kSpacing);
  }

  // The oracle at cutter locations on a profile arc (line 186, Z9), a profile line (line 185) and
  // a pocket zig-zag line at the third level (Z12).
  for (const int line : {186, 185, 101}) {
    SCOPED_TRACE(testing::Message() << "line " << line);
    std::size_t k = 0;
    while (k < samples.size() && samples[k].cl.line != line) ++k;
    ASSERT_LT(k, samples.size());
    // Halfway along the move.
    while (k + 1 < samples.size() && samples[k + 1].cl.line == line && samples[k].cl.u < 0.5) ++k;
    const Sample& s = samples[k];
    ASSERT_TRUE(s.map.engaged);
    const double u_next = k + 1 < samples.size() && samples[k + 1].cl.move == s.cl.move
                              ? samples[k + 1].cl.u
                              : 1.0;
    const test::OracleCount checked = test::check_against_oracle(
        cutter, block, path.moves, s.cl, s.state, s.map, u_next, kSpacing);
    EXPECT_GT(checked.agreed, 200);
    EXPECT_GT(checked.engaged, 20);
  }
}

}  // namespace
}  // namespace cwe
