#pragma once
/// Dry air at 1 atm as a smooth function of temperature, with derivatives, for convection
/// correlations.
///
/// Values interpolate Incropera et al., Fundamentals of Heat and Mass Transfer, Table A.4 at
/// 200, 250, 300, 350 and 400 K with the quartic through those five points (exact at the table
/// points, infinitely smooth in between). Outside 200-400 K the temperature is clamped: values
/// stay at the end-point values and their derivatives are zero there.

namespace thermnet::air {

/// Lowest temperature of the fitted range, K.
inline constexpr double T_min = 200.0;
/// Highest temperature of the fitted range, K.
inline constexpr double T_max = 400.0;

/// Properties of air at one temperature and their derivatives with respect to temperature.
struct Properties {
  double k = 0.0;      ///< thermal conductivity, W/(m K)
  double dk = 0.0;     ///< dk/dT, W/(m K^2)
  double nu = 0.0;     ///< kinematic viscosity, m^2/s
  double dnu = 0.0;    ///< dnu/dT, m^2/(s K)
  double alpha = 0.0;  ///< thermal diffusivity, m^2/s
  double dalpha = 0.0; ///< dalpha/dT, m^2/(s K)
  double Pr = 0.0;     ///< Prandtl number
  double dPr = 0.0;    ///< dPr/dT, 1/K
};

/// Properties of dry air at 1 atm at temperature T in kelvin (clamped to [T_min, T_max]).
Properties properties(double T);

} // namespace thermnet::air
