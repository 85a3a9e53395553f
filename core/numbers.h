// hipfai — the numeric constants every module uses, defined once.
#pragma once

#include <limits>
#include <numbers>

namespace hipfai {

// Marks a value that is missing or undefined (an empty cell, a step without contact).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace hipfai
