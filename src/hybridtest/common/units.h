#pragma once
// Unit conventions. Everything inside hybridtest is SI: m, kg, s, N, rad, N·m.
// Conversions to other units happen only at the hardware seam (transfer systems and setup
// transforms), using the factors below, and every config key that is not SI says its unit in
// its name (stroke_mm).
namespace hybridtest::units {

inline constexpr double kMillimetre = 1e-3;  // [m] per [mm]
inline constexpr double kKilonewton = 1e3;   // [N] per [kN]
inline constexpr double kMillisecond = 1e-3; // [s] per [ms]

}  // namespace hybridtest::units
