// The effective options of a subcommand: every option, given or default, typed; flags as booleans.
#include "command_provenance.h"

#include <gtest/gtest.h>

namespace ramtk::tools {
namespace {

TEST(CommandProvenance, EveryOptionWithItsEffectiveValue) {
  CLI::App app{"test"};
  CLI::App* sub = app.add_subcommand("scan", "");
  std::string set, out = "scan_out", roi = "full";
  double radius = 19.05, depth = 100;
  int jobs = 2;
  bool quiet = false, force = false;
  std::vector<std::string> with;
  std::vector<int> poses = {3, 4}, none;
  sub->add_option("set", set, "");
  sub->add_option("--out", out, "");
  sub->add_option("--radius", radius, "");
  sub->add_option("--min-depth", depth, "")->capture_default_str();
  sub->add_option("--jobs", jobs, "");
  sub->add_option("--roi", roi, "");
  sub->add_option("--with", with, "");
  sub->add_option("--poses", poses, "");
  sub->add_option("--none", none, "");
  sub->add_flag("-q,--quiet", quiet, "");
  sub->add_flag("--force", force, "");
  const char* argv[] = {"ramtk", "scan", "m.json", "--radius", "12.5", "-q", "--with", "a", "--with", "b"};
  app.parse(10, const_cast<char**>(argv));
  const nlohmann::json o = EffectiveOptions(sub);
  EXPECT_EQ(o.size(), 11u) << o.dump();  // --help is not an option of the run
  EXPECT_EQ(o["poses"], nlohmann::json::array({3, 4}));
  EXPECT_EQ(o["none"], nlohmann::json::array());
  EXPECT_EQ(o["set"], "m.json");
  EXPECT_EQ(o["out"], "scan_out");
  EXPECT_EQ(o["radius"], 12.5);
  EXPECT_EQ(o["min-depth"], 100);
  EXPECT_EQ(o["jobs"], 2);
  EXPECT_EQ(o["roi"], "full");
  EXPECT_EQ(o["with"], nlohmann::json::array({"a", "b"}));
  EXPECT_EQ(o["quiet"], true);
  EXPECT_EQ(o["force"], false);
}

}  // namespace
}  // namespace ramtk::tools
