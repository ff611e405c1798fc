// Sequence specs read and written through the codec table (sequence_spec.h).
#include "ramtk/vision/fringe/sequence_spec.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "ramtk/core/parse.h"
#include "ramtk/vision/fringe/codec.h"

namespace ramtk::vision {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

std::string Number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string SpecName(const PatternCodec& codec) { return codec.spec_name.empty() ? codec.name : codec.spec_name; }

bool IsFlag(const CodecParameter& p) { return p.field == CodecField::kComplementary; }

// "STEPS", "PHASE_AT_ORIGIN_DEG".
std::string Placeholder(const CodecParameter& p) {
  std::string s;
  for (char ch : p.key) s += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

// The forms of one codec: one per combination of its flags' prefixes (none, each one).
std::vector<std::string> Forms(const PatternCodec& codec) {
  std::string fields;
  for (const CodecParameter& p : codec.parameters) {
    if (IsFlag(p)) continue;
    std::string f = Placeholder(p);
    if (p.max_count > 1) {
      f = Placeholder(p) + "1";
      for (int i = 2; i <= p.max_count; ++i)
        f += i <= p.min_count ? "/" + Placeholder(p) + std::to_string(i)
                              : "[/" + Placeholder(p) + std::to_string(i) + "]";
    }
    fields += p.required ? ":" + f : "[:" + f + "]";
  }
  std::vector<std::string> forms = {SpecName(codec) + fields};
  for (const CodecParameter& p : codec.parameters)
    if (IsFlag(p) && !p.spec_prefix.empty()) forms.push_back(p.spec_prefix + SpecName(codec) + fields);
  return forms;
}

// The codec a block name spells and the flags its prefix sets, or nullptr.
const PatternCodec* FindSpecCodec(const std::string& name, std::vector<const CodecParameter*>* flags) {
  for (const PatternCodec* c : PatternCodecs()) {
    for (const std::string& base : {SpecName(*c), c->name}) {
      if (name == base) return c;
      for (const CodecParameter& p : c->parameters) {
        if (!IsFlag(p) || p.spec_prefix.empty() || name != p.spec_prefix + base) continue;
        flags->push_back(&p);
        return c;
      }
    }
  }
  return nullptr;
}

// A value of an integer or number parameter, checked against the table's range.
double Value(const std::string& text, const CodecParameter& p, const InputLocation& where, const std::string& token) {
  const double v = ParseDouble(text, where);
  const bool integer = p.field == CodecField::kSteps || p.field == CodecField::kBits;
  const bool ok = p.field == CodecField::kCycles ? v > p.min && v <= p.max : v >= p.min && v <= p.max;
  if (!ok || (integer && v != std::floor(v)))
    throw InputError(where, "sequence block '" + token + "': " + p.key + " expects " + CodecParameterAccepted(p) +
                                ", got '" + text + "'");
  return v;
}

// Sets parameter p of `block` from fields[*next...], advancing *next.
void Fill(const CodecParameter& p, const std::vector<std::string>& fields, std::size_t* next,
          const InputLocation& where, const std::string& token, SequenceBlock* block) {
  const std::string& field = fields[(*next)++];
  switch (p.field) {
    case CodecField::kSteps:
      block->steps = static_cast<int>(Value(field, p, where, token));
      break;
    case CodecField::kBits:
      block->bits = static_cast<int>(Value(field, p, where, token));
      break;
    case CodecField::kPhaseAtOrigin:
      block->phase_at_origin_rad = Value(field, p, where, token) * kPi / 180.0;
      break;
    case CodecField::kCycles: {
      std::vector<std::string> values = {field};
      if (p.max_count > 1 && field.find('/') != std::string::npos) {
        values = Split(field, '/');
      } else {
        while (p.max_count > 1 && *next < fields.size() && static_cast<int>(values.size()) < p.max_count)
          values.push_back(fields[(*next)++]);
      }
      if (static_cast<int>(values.size()) < p.min_count || static_cast<int>(values.size()) > p.max_count)
        throw InputError(where, "sequence block '" + token + "': " + p.key + " expects " + std::to_string(p.min_count) +
                                    " to " + std::to_string(p.max_count) + " values, got " +
                                    std::to_string(values.size()));
      block->cycles.clear();
      for (const std::string& v : values) block->cycles.push_back(Value(v, p, where, token));
      break;
    }
    case CodecField::kComplementary:
      break;
  }
}

SequenceBlock ParseBlock(const std::string& token, const InputLocation& where) {
  const std::vector<std::string> f = Split(token, ':');
  std::vector<const CodecParameter*> flags;
  const PatternCodec* codec = f.empty() ? nullptr : FindSpecCodec(f[0], &flags);
  if (!codec)
    throw InputError(where, "unknown sequence block '" + token + "': the codec table has " + SequenceSpecForms());
  SequenceBlock block = codec->type == BlockType::kRegistered ? RegisteredBlock(codec->name) : SequenceBlock{};
  block.type = codec->type;
  if (!flags.empty()) block.complementary = true;  // the only flag parameter
  std::size_t next = 1;
  for (const CodecParameter& p : codec->parameters) {
    if (IsFlag(p)) continue;
    if (next < f.size()) {
      Fill(p, f, &next, where, token, &block);
    } else if (p.required) {
      throw InputError(where, "sequence block '" + token + "' lacks " + Placeholder(p) + " (expected " +
                                  Forms(*codec).front() + ")");
    }
  }
  if (next < f.size())
    throw InputError(where,
                     "sequence block '" + token + "' has too many values (expected " + Forms(*codec).front() + ")");
  return block;
}

}  // namespace

std::vector<SequenceBlock> ParseSequenceSpec(const std::string& text, const InputLocation& where) {
  std::vector<SequenceBlock> blocks;
  for (const std::string& token : Split(text, ',')) blocks.push_back(ParseBlock(token, where));
  if (blocks.empty()) throw InputError(where, "empty sequence");
  return blocks;
}

std::string SequenceSpec(const std::vector<SequenceBlock>& sequence) {
  const SequenceBlock defaults;
  std::string out;
  for (const SequenceBlock& b : sequence) {
    const PatternCodec& codec = CodecOf(b);
    std::string name = SpecName(codec);
    for (const CodecParameter& p : codec.parameters)
      if (IsFlag(p) && b.complementary) name = p.spec_prefix + name;
    std::vector<std::string> fields;
    for (const CodecParameter& p : codec.parameters) {
      if (p.field == CodecField::kSteps) fields.push_back(std::to_string(b.steps));
      if (p.field == CodecField::kBits) fields.push_back(std::to_string(b.bits));
      if (p.field == CodecField::kCycles) {
        std::string c;
        for (double v : b.cycles) c += (c.empty() ? "" : "/") + Number(v);
        fields.push_back(c);
      }
      if (p.field == CodecField::kPhaseAtOrigin && b.phase_at_origin_rad != defaults.phase_at_origin_rad)
        fields.push_back(Number(b.phase_at_origin_rad * 180.0 / kPi));
    }
    // Several values written as the last fields take one field each.
    if (!fields.empty()) std::replace(fields.back().begin(), fields.back().end(), '/', ':');
    out += (out.empty() ? "" : ",") + name;
    for (const std::string& f : fields) out += ":" + f;
  }
  return out;
}

std::string SequenceSpecForms() {
  std::string s;
  for (const PatternCodec* c : PatternCodecs())
    for (const std::string& form : Forms(*c)) s += (s.empty() ? "" : ", ") + form;
  return s;
}

}  // namespace ramtk::vision
