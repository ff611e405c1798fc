#pragma once
// Sequence specs: a projected sequence written on one line ("ps:12:64,cgc:7"), read and written
// through the codec table (codec.h). A block is NAME:VALUE:VALUE..., NAME the codec's spec_name
// (or its name), preceded by the spec_prefix of each boolean parameter that is true ("cgc" = a
// complementary Gray code). The values fill the codec's other parameters in the table's order;
// optional ones at the end may be left out; a parameter of several values takes them '/'-separated
// in one field (het:4:70/64/59) or, when it is the last one given, the remaining fields
// (het:4:64:56). Phases are in degrees.

#include <string>
#include <vector>

#include "ramtk/core/error.h"
#include "ramtk/vision/fringe/manifest.h"

namespace ramtk::vision {

// Comma-separated blocks in projection order. InputError naming `where` for an empty spec, a
// name not in the codec table (the message lists the table's forms) or a value out of range.
std::vector<SequenceBlock> ParseSequenceSpec(const std::string& text, const InputLocation& where);
// The spec of a sequence (the inverse of ParseSequenceSpec); optional parameters at their
// defaults are left out.
std::string SequenceSpec(const std::vector<SequenceBlock>& sequence);
// Every block form the codec table accepts, comma-separated, e.g.
// "ps:STEPS:CYCLES[:PHASE_AT_ORIGIN_DEG], gc:BITS, cgc:BITS, ...".
std::string SequenceSpecForms();

}  // namespace ramtk::vision
