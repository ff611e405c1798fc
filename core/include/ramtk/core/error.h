#pragma once
// Errors for bad user input. A broken invariant inside ramtk is a bug and may abort; input that
// is wrong (a file, a field, a command-line value) is reported with an InputError whose message
// names where the problem is, so the user can fix it.

#include <stdexcept>
#include <string>

namespace ramtk {

// Where a bad value came from. Any part may be empty / zero.
struct InputLocation {
  std::string file;   // path of the file, or "" for command-line values
  int line = 0;       // 1-based line number, 0 if unknown
  std::string field;  // field, key or option name, e.g. "joints[2].alpha" or "--joints"
};

// Bad user input. what() reads "file:line: field 'name': message".
class InputError : public std::runtime_error {
 public:
  InputError(InputLocation where, const std::string& message);
  const InputLocation& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  InputLocation where_;
  std::string message_;
};

// The options contract. Every Options struct has `std::string Validate() const`: "" when the
// options are usable, else one problem, "field: what is wrong". A nested struct's problem is
// prefixed with its member name ("decode.nonlinearity.orders: expected 1..6").
// A problem split into its leading field name (letters, digits, '_', '.', '[', ']') and the rest;
// the field is "" when the problem does not start with one.
struct OptionsProblem {
  std::string field, message;
};
OptionsProblem SplitOptionsProblem(const std::string& problem);
// Throws InputError({"", 0, field}, message) for a non-empty problem; `options_name` is the field
// when the problem names none.
void ThrowIfInvalid(const std::string& problem, const std::string& options_name);

// The one check of a noise level (a σ) in an Options' Validate: "" when 0 <= value <= max (NaN and
// infinity fail), else "field: expected a noise sigma in [0, max] unit, got value". The limits are
// far beyond any instrument's noise: a larger value is a typing error (1e308, a unit slip).
inline constexpr double kMaxNoiseMm = 100.0;  // σ of a position, a length or a repeatability
inline constexpr double kMaxNoiseDeg = 10.0;  // σ of an angle
inline constexpr double kMaxNoiseS = 1.0;     // σ of a time
inline constexpr double kMaxNoiseK = 100.0;   // σ of a temperature
std::string CheckNoise(const std::string& field, double value, double max, const char* unit);

// Formats a location as "file:line: field 'name'" (parts that are empty are left out).
std::string FormatLocation(const InputLocation& where);

}  // namespace ramtk
