#include "ramtk/diagnose/laser/laser_hidden.h"

#include <random>

namespace ramtk::diagnose {

std::vector<std::string> DrawnLaserEffects() {
  std::vector<std::string> out;
#define RAMTK_LASER_CAUSE(name, drawn, fitted, parameters, plausible, help) \
  if (drawn) out.push_back(#name);
#include "ramtk/diagnose/engine/laser_causes.def"
  return out;
}

HiddenLaserEffect DrawHiddenLaserEffect(std::uint64_t seed) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 12345u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  auto sign = [&]() { return unit(rng) < 0.5 ? -1.0 : 1.0; };
  HiddenLaserEffect h;
  tcf::TcfSimulationOptions& o = h.options;
  o.seed = seed;
  // A different bent tool each draw.
  o.tool_psi_deg = uniform(-180.0, 180.0);
  o.tool_theta_deg = uniform(1.0, 4.0);
  o.tcp_in_flange = Vec3(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(149.0, 152.0));
  const std::vector<std::string> effects = DrawnLaserEffects();
  const int pick = static_cast<int>(unit(rng) * 3.0 * effects.size() / 2.0);  // 1/3 none
  h.effect = pick < static_cast<int>(effects.size()) ? effects[pick] : "none";
  tcf::DeviceEffects& fx = o.effects;
  if (h.effect != "none") fx.Enable(h.effect);
  if (h.effect == "beam_non_perpendicular") {
    fx.beta_deg = 90.0 + sign() * uniform(0.5, 3.0);
    h.parameter = "beta_deg", h.magnitude = fx.beta_deg;
  } else if (h.effect == "beam_offset") {
    fx.beam_offset_mm = sign() * uniform(0.15, 0.8);
    h.parameter = "offset_mm", h.magnitude = fx.beam_offset_mm;
  } else if (h.effect == "beam_width") {
    fx.beam_width_mm = uniform(0.3, 1.5);
    h.parameter = "width_mm", h.magnitude = fx.beam_width_mm;
  } else if (h.effect == "trigger_latency") {
    fx.latency_s = 1e-3 * uniform(2.0, 15.0);
    h.parameter = "latency_ms", h.magnitude = fx.latency_s * 1e3;
  } else if (h.effect == "speed_variation") {
    fx.speed_scale_error = 0.01 * sign() * uniform(0.5, 3.0);
    fx.speed_ripple = 0.0;
    h.parameter = "speed_error_percent", h.magnitude = fx.speed_scale_error * 100.0;
  }
  h.simulation = tcf::SimulateTcf(o);
  return h;
}

}  // namespace ramtk::diagnose
