// The provenance block: XXH3-128 against xxhsum's digests, the block appended to a JSON
// text without touching what is there, the run group apart, shell quoting.
#include "ramtk/core/provenance.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"

namespace ramtk {
namespace {

// The digests below are what xxHash's own command line prints (`xxhsum -H2`, xxHash 0.8.1).
TEST(Provenance, Xxh3MatchesXxhsum) {
  EXPECT_EQ(Xxh3Of(""), "99aa06d3014798d86001c324468d497f");
  EXPECT_EQ(Xxh3Of("abc"), "06b05ab6733a618578af5f94892f3950");
  EXPECT_EQ(Xxh3Of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"), "3d62d22a5169b016c0d894fd4828a1a7");
}

TEST(Provenance, FileHashReadsEveryBlock) {
  // One million 'a' and 1 MiB of 'b' span the reader's 1 MiB block boundary.
  const std::string path = (std::filesystem::temp_directory_path() / "ramtk_provenance_a.bin").string();
  std::ofstream(path, std::ios::binary) << std::string(1000000, 'a') << std::string(1 << 20, 'b');
  Provenance p;
  AddProvenanceInput(&p, path, "data/a.bin");
  AddProvenanceInput(&p, path, "data/a.bin");  // listed once
  ASSERT_EQ(p.inputs.size(), 1u);
  EXPECT_EQ(p.inputs[0].path, "data/a.bin");
  EXPECT_EQ(p.inputs[0].bytes, 1000000u + (1u << 20));
  EXPECT_EQ(p.inputs[0].xxh3_128, "621197f7197349bac2789462314fd0b4");
  EXPECT_EQ(p.inputs[0].xxh3_128, Xxh3Of(std::string(1000000, 'a') + std::string(1 << 20, 'b')));
  std::ofstream(path, std::ios::binary) << std::string(1000000, 'a');
  EXPECT_EQ(Xxh3OfFile(path), "a545df8e384a9579b1fd6fae5285c4eb");
  std::filesystem::remove(path);
  EXPECT_THROW(Xxh3OfFile(path), InputError);
}

TEST(Provenance, BlockIsAppendedAsTheLastMember) {
  Provenance p = StartProvenance({"ramtk", "scan", "a b.json", "--out", "o"}, {{"radius", 19.05}, {"quiet", true}});
  AddProvenanceInput(&p, "");  // nothing to hash
  const std::string text = "{\n  \"format\": \"x\",\n  \"values\": [\n    1,\n    2\n  ]\n}\n";
  const std::string out = WithProvenance(text, p);
  // What was there is unchanged, byte for byte, up to the new member.
  EXPECT_EQ(out.substr(0, text.size() - 3), text.substr(0, text.size() - 3));
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["format"], "x");
  EXPECT_EQ(j["provenance"]["command"][2], "a b.json");
  EXPECT_EQ(j["provenance"]["options"]["radius"], 19.05);
  EXPECT_EQ(j["provenance"]["ramtk_version"], RamtkVersion());
  EXPECT_FALSE(RamtkGitCommit().empty());
  // The run group holds every member that changes from run to run.
  const nlohmann::json& run = j["provenance"]["run"];
  for (const char* key : {"started_utc", "host", "working_directory", "elapsed_s"}) EXPECT_TRUE(run.contains(key)) << key;
  EXPECT_EQ(j["provenance"].size(), 6u);
  // An empty object, and text that is no object.
  EXPECT_TRUE(nlohmann::json::parse(WithProvenance("{}\n", p)).contains("provenance"));
  EXPECT_EQ(WithProvenance("[1, 2]\n", p), "[1, 2]\n");
}

TEST(Provenance, CommandLineIsQuotedForTheShell) {
  EXPECT_EQ(ShellCommandLine({"ramtk", "scan", "--out", "/tmp/a b", "it's", "--roi=1,2,3"}),
            "ramtk scan --out '/tmp/a b' 'it'\\''s' --roi=1,2,3");
  EXPECT_EQ(ShellCommandLine({"x", ""}), "x ''");
}

}  // namespace
}  // namespace ramtk
