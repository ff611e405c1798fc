// Shared helpers of the independent generators (issue 15): options, truth record, file writing.
// Nothing here comes from ramtk: the generators must not share code with what they test.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace indep {

struct GenOptions {
  std::string kind;    // fringe | robot | laser
  std::string effect;  // effect name (see README.md)
  unsigned seed = 1;   // fixed seed -> identical output
  double magnitude = std::nan("");  // effect size in the effect's unit; NaN = the documented default
  double gain = 1.0;   // fringe: camera conversion gain, DN (16-bit) per electron
  int sub = 2;         // fringe: n×n rays per camera pixel (1: point sampling, the pixel's centre ray)
  std::string out_dir;
  std::string robot_path;  // robot: model YAML (default: datasets/robots/kuka_kr150_r3100.yaml)
};

// What the data hold, for the sweep: `expected` is the one right verdict; `accepted` lists every
// verdict that counts as correct (e.g. `unexplained` for an effect outside today's catalogue).
struct Truth {
  std::string kind, effect, expected;
  std::vector<std::string> accepted;
  std::string explaining_variable;  // for effects outside the catalogue ("q4", "time in segment")
  nlohmann::json parameters = nlohmann::json::object();
};

// Writes text to path via a temporary file and rename; throws std::runtime_error on failure.
void WriteFileAtomic(const std::string& path, const std::string& text);
void WriteTruth(const std::string& dir, const Truth& truth, const GenOptions& options);

// Deterministic random source: a 64-bit Mersenne twister with explicit algorithms for the normal
// (Box–Muller) and Poisson draws so that the output does not depend on the standard library.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double Uniform() { return (static_cast<double>(engine_() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  double Normal();
  // Exact Poisson draw: Knuth's product method below a mean of 10, Hörmann's PTRS above.
  double Poisson(double mean);

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace indep
