#pragma once
// Units. Files and command lines use millimetres and degrees; library code uses millimetres and
// radians. Convert at the boundary with these helpers, nowhere else.

namespace ramtk {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kDegPerRad = 180.0 / kPi;
inline constexpr double kArcsecPerRad = kDegPerRad * 3600.0;

constexpr double DegToRad(double deg) { return deg * kRadPerDeg; }
constexpr double RadToDeg(double rad) { return rad * kDegPerRad; }

}  // namespace ramtk
