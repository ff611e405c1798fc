#pragma once
// Parsing of numbers from user text (command lines, CSV cells) with errors that name the field.

#include <string>
#include <vector>

#include "ramtk/core/error.h"

namespace ramtk {

// Parses a whole string as a finite double ("1e3", " -2.5 "); throws InputError at `where`.
double ParseDouble(const std::string& text, const InputLocation& where);
// Half the last printed digit of a decimal number ("0.707107" -> 5e-7, "1.5e-3" -> 5e-5, "12" ->
// 0.5): how far the printed value may be from the value it was rounded from.
double PrintedRoundingBound(const std::string& text);

// Parses "a,b,c" into doubles. If expected_count > 0 the count must match. Throws InputError.
std::vector<double> ParseDoubleList(const std::string& text, const InputLocation& where,
                                    int expected_count = 0);

}  // namespace ramtk
