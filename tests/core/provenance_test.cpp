// The provenance block: SHA-256 against the FIPS 180-2 examples, the block appended to a JSON
// text without touching what is there, the run group apart, shell quoting.
#include "ramtk/core/provenance.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"

namespace ramtk {
namespace {

TEST(Provenance, Sha256MatchesTheStandardExamples) {
  // FIPS 180-2, appendix B.1 and B.2; the empty message.
  EXPECT_EQ(Sha256Of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Provenance, FileHashReadsEveryBlock) {
  // One million 'a' (FIPS 180-2 B.3) spans the reader's 1 MiB block boundary.
  const std::string path = (std::filesystem::temp_directory_path() / "ramtk_provenance_a.bin").string();
  std::ofstream(path, std::ios::binary) << std::string(1000000, 'a') << std::string(1 << 20, 'b');
  Provenance p;
  AddProvenanceInput(&p, path, "data/a.bin");
  AddProvenanceInput(&p, path, "data/a.bin");  // listed once
  ASSERT_EQ(p.inputs.size(), 1u);
  EXPECT_EQ(p.inputs[0].path, "data/a.bin");
  EXPECT_EQ(p.inputs[0].bytes, 1000000u + (1u << 20));
  EXPECT_EQ(p.inputs[0].sha256, Sha256Of(std::string(1000000, 'a') + std::string(1 << 20, 'b')));
  std::ofstream(path, std::ios::binary) << std::string(1000000, 'a');
  EXPECT_EQ(Sha256OfFile(path), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  std::filesystem::remove(path);
  EXPECT_THROW(Sha256OfFile(path), InputError);
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
