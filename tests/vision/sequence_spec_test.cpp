// Sequence specs read through the codec table: the named block constructors' blocks from their
// specs, every form of every table row round-tripping, a codec registered at run time readable by
// its name, and refusals that name the table's forms or the offending parameter.
#include "ramtk/vision/fringe/sequence_spec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/codec.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

void ExpectSameBlock(const SequenceBlock& a, const SequenceBlock& b, const std::string& what) {
  EXPECT_EQ(a.type, b.type) << what;
  EXPECT_EQ(a.codec, b.codec) << what;
  EXPECT_EQ(a.steps, b.steps) << what;
  EXPECT_EQ(a.bits, b.bits) << what;
  EXPECT_EQ(a.complementary, b.complementary) << what;
  EXPECT_EQ(a.cycles, b.cycles) << what;
  EXPECT_NEAR(a.phase_at_origin_rad, b.phase_at_origin_rad, 1e-12) << what;
}

std::string Refusal(const std::string& spec) {
  try {
    ParseSequenceSpec(spec, {"", 0, "--sequence"});
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << spec << " was accepted";
  return "";
}

TEST(SequenceSpec, ReadsTheNamedConstructorsBlocks) {
  const std::vector<SequenceBlock> s =
      ParseSequenceSpec("ps:12:64,cgc:7,gc:3,het:4:70/64/59,het:4:64:56,ps:4:16:-90,phase_shift:3:8", {});
  ASSERT_EQ(s.size(), 7u);
  ExpectSameBlock(s[0], PhaseShiftBlock(12, 64), "ps");
  ExpectSameBlock(s[1], GrayCodeBlock(7, true), "cgc");
  ExpectSameBlock(s[2], GrayCodeBlock(3, false), "gc");
  ExpectSameBlock(s[3], HeterodyneBlock(4, {70, 64, 59}), "het with /");
  ExpectSameBlock(s[4], HeterodyneBlock(4, {64, 56}), "het with :");
  ExpectSameBlock(s[5], PhaseShiftBlock(4, 16, -kPi / 2), "ps with phase");
  ExpectSameBlock(s[6], PhaseShiftBlock(3, 8), "the codec's full name");
  EXPECT_EQ(SequenceSpec({s[0], s[1], s[2], s[4]}), "ps:12:64,cgc:7,gc:3,het:4:64:56");
  EXPECT_EQ(SequenceSpec({s[3], s[5]}), "het:4:70:64:59,ps:4:16:-90");
}

// One block of `codec` with every parameter inside the table's range (flags as given).
SequenceBlock InRangeBlock(const PatternCodec& codec, bool flags, bool optional) {
  SequenceBlock b = codec.type == BlockType::kRegistered ? RegisteredBlock(codec.name) : SequenceBlock{};
  b.type = codec.type;
  for (const CodecParameter& p : codec.parameters) {
    if (!p.required && !optional) continue;
    if (p.field == CodecField::kSteps) b.steps = static_cast<int>(p.min) + 1;
    if (p.field == CodecField::kBits) b.bits = static_cast<int>(p.min) + 1;
    if (p.field == CodecField::kComplementary) b.complementary = flags;
    if (p.field == CodecField::kPhaseAtOrigin) b.phase_at_origin_rad = -kPi / 4;
    if (p.field == CodecField::kCycles)
      for (int i = 0; i < p.max_count; ++i) b.cycles.push_back(p.min + 40.5 - 3 * i);
  }
  return b;
}

TEST(SequenceSpec, EveryTableRowRoundTrips) {
  int forms = 0;
  for (const PatternCodec* codec : PatternCodecs()) {
    for (bool flags : {false, true}) {
      for (bool optional : {false, true}) {
        const SequenceBlock block = InRangeBlock(*codec, flags, optional);
        const std::string spec = SequenceSpec({block});
        const std::vector<SequenceBlock> back = ParseSequenceSpec(spec, {});
        ASSERT_EQ(back.size(), 1u) << spec;
        ExpectSameBlock(back[0], block, codec->name + " as " + spec);
        EXPECT_NE(SequenceSpecForms().find(spec.substr(0, spec.find(':')) + ":"), std::string::npos) << spec;
        ++forms;
      }
    }
  }
  EXPECT_EQ(forms, 4 * static_cast<int>(PatternCodecs().size()));
}

TEST(SequenceSpec, ReadsACodecRegisteredAtRunTime) {
  PatternCodec c;
  c.name = "test_spec_ramp";
  c.spec_name = "tsr";
  c.role = CodecRole::kAbsolute;
  c.help = "a ramp";
  c.parameters = {{"steps", CodecField::kSteps, true, 2, 9, 1, 1, "", "images"}};
  c.image_count = [](const SequenceBlock& b) { return b.steps; };
  c.intensity = [](const SequenceBlock&, int, double u, int extent) { return u / extent; };
  c.decode = [](const SequenceBlock&, const std::vector<cv::Mat>&, int, double) { return CodecDecodeResult{}; };
  RegisterPatternCodec(c);
  EXPECT_NE(SequenceSpecForms().find("tsr:STEPS"), std::string::npos);
  const std::vector<SequenceBlock> s = ParseSequenceSpec("ps:12:64,tsr:5", {});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].type, BlockType::kRegistered);
  EXPECT_EQ(s[1].codec, "test_spec_ramp");
  EXPECT_EQ(s[1].steps, 5);
  EXPECT_EQ(SequenceSpec(s), "ps:12:64,tsr:5");
  EXPECT_NE(Refusal("tsr:10").find("steps expects integer 2..9, got '10'"), std::string::npos);
  UnregisterPatternCodec(c.name);
  EXPECT_EQ(SequenceSpecForms().find("tsr"), std::string::npos);
}

TEST(SequenceSpec, RefusesUnknownNamesListingTheTable) {
  const std::string message = Refusal("ps:12:64,xx:3");
  EXPECT_NE(message.find("--sequence"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown sequence block 'xx:3': the codec table has"), std::string::npos) << message;
  for (const PatternCodec* c : PatternCodecs())
    EXPECT_NE(message.find((c->spec_name.empty() ? c->name : c->spec_name) + ":"), std::string::npos) << c->name;
  EXPECT_NE(message.find("cgc:BITS"), std::string::npos) << message;
}

TEST(SequenceSpec, RefusesValuesOutsideTheTable) {
  EXPECT_NE(Refusal("ps:12").find("lacks CYCLES"), std::string::npos);
  EXPECT_NE(Refusal("ps:2:64").find("steps expects integer >= 3, got '2'"), std::string::npos);
  EXPECT_NE(Refusal("ps:3.5:64").find("steps expects"), std::string::npos);
  EXPECT_NE(Refusal("gc:17").find("bits expects integer 1..16, got '17'"), std::string::npos);
  EXPECT_NE(Refusal("ps:12:64:400").find("phase_at_origin_deg expects number in [-360, 360]"), std::string::npos);
  EXPECT_NE(Refusal("het:4:64").find("cycles expects 2 to 3 values, got 1"), std::string::npos);
  EXPECT_NE(Refusal("het:4:70/64/59/50").find("cycles expects 2 to 3 values, got 4"), std::string::npos);
  EXPECT_NE(Refusal("ps:12:64:0:1").find("too many values"), std::string::npos);
  EXPECT_NE(Refusal("ps:12:-64").find("cycles expects"), std::string::npos);
  EXPECT_NE(Refusal("").find("empty sequence"), std::string::npos);
}

}  // namespace
}  // namespace ramtk::vision
