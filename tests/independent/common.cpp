#include "common.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace indep {

void WriteFileAtomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out << text;
    if (!out) throw std::runtime_error("write failed: " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot rename to " + path);
}

void WriteTruth(const std::string& dir, const Truth& truth, const GenOptions& options) {
  nlohmann::json j;
  j["generator"] = "ramtk_indep_gen (tests/independent, written from the physics only)";
  j["kind"] = truth.kind;
  j["effect"] = truth.effect;
  j["seed"] = options.seed;
  j["parameters"] = truth.parameters;
  j["expected_verdict"] = truth.expected;
  j["accepted_verdicts"] = truth.accepted;
  if (!truth.explaining_variable.empty()) j["explaining_variable"] = truth.explaining_variable;
  WriteFileAtomic(dir + "/truth.json", j.dump(2) + "\n");
}

double Rng::Normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double u1 = Uniform(), u2 = Uniform();
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * M_PI * u2);
  has_spare_ = true;
  return r * std::cos(2.0 * M_PI * u2);
}

double Rng::Poisson(double mean) {
  if (mean <= 0) return 0;
  if (mean < 10) {  // Knuth: multiply uniforms until the product falls below exp(-mean)
    const double limit = std::exp(-mean);
    double product = Uniform();
    int k = 0;
    while (product > limit) {
      product *= Uniform();
      ++k;
    }
    return k;
  }
  // Hörmann (1993), "The transformed rejection method for generating Poisson random variables"
  // (PTRS): exact for every mean >= 10.
  const double slam = std::sqrt(mean), loglam = std::log(mean);
  const double b = 0.931 + 2.53 * slam, a = -0.059 + 0.02483 * b;
  const double inv_alpha = 1.1239 + 1.1328 / (b - 3.4), vr = 0.9277 - 3.6224 / (b - 2);
  for (;;) {
    const double u = Uniform() - 0.5, v = Uniform();
    const double us = 0.5 - std::fabs(u);
    const double k = std::floor((2 * a / us + b) * u + mean + 0.43);
    if (us >= 0.07 && v <= vr) return k;
    if (k < 0 || (us < 0.013 && v > us)) continue;
    if (std::log(v) + std::log(inv_alpha) - std::log(a / (us * us) + b) <=
        -mean + k * loglam - std::lgamma(k + 1)) {
      return k;
    }
  }
}

}  // namespace indep
