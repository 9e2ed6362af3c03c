#pragma once
/// Physical dimensions and the units table: parsing "W/(m^2*K)" into an SI scale and dimension.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace thermnet::lang {

/// 0 degC in kelvin (temperatures are kelvin inside, degC in files and reports).
inline constexpr double kZeroCelsius = 273.15;

/// Exponents of the SI base dimensions, in the order m, kg, s, K, A, mol, cd.
struct Dimension {
  std::array<std::int8_t, 7> exp{}; ///< exponent of each base dimension

  /// Product of two dimensions (exponents add).
  constexpr Dimension operator*(const Dimension& o) const {
    Dimension r;
    for (std::size_t i = 0; i < exp.size(); ++i)
      r.exp[i] = static_cast<std::int8_t>(exp[i] + o.exp[i]);
    return r;
  }
  /// Quotient of two dimensions (exponents subtract).
  constexpr Dimension operator/(const Dimension& o) const {
    Dimension r;
    for (std::size_t i = 0; i < exp.size(); ++i)
      r.exp[i] = static_cast<std::int8_t>(exp[i] - o.exp[i]);
    return r;
  }
  /// Integer power of a dimension.
  constexpr Dimension pow(int n) const {
    Dimension r;
    for (std::size_t i = 0; i < exp.size(); ++i)
      r.exp[i] = static_cast<std::int8_t>(exp[i] * n);
    return r;
  }
  /// True when every exponent is zero.
  constexpr bool dimensionless() const {
    for (auto e : exp)
      if (e != 0) return false;
    return true;
  }
  /// Exponent-wise equality.
  constexpr bool operator==(const Dimension&) const = default;
};

/// Named dimensions used by element schemas and messages.
namespace dim {
inline constexpr Dimension none{};                                   ///< dimensionless
inline constexpr Dimension length{{1, 0, 0, 0, 0, 0, 0}};            ///< m
inline constexpr Dimension mass{{0, 1, 0, 0, 0, 0, 0}};              ///< kg
inline constexpr Dimension time{{0, 0, 1, 0, 0, 0, 0}};              ///< s
inline constexpr Dimension temperature{{0, 0, 0, 1, 0, 0, 0}};       ///< K
inline constexpr Dimension area = length * length;                   ///< m^2
inline constexpr Dimension energy{{2, 1, -2, 0, 0, 0, 0}};           ///< J
inline constexpr Dimension power{{2, 1, -3, 0, 0, 0, 0}};            ///< W
inline constexpr Dimension capacity = energy / temperature;          ///< J/K
inline constexpr Dimension conductance = power / temperature;        ///< W/K
inline constexpr Dimension resistance = temperature / power;         ///< K/W
inline constexpr Dimension conductivity = conductance / length;      ///< W/(m*K)
inline constexpr Dimension heat_transfer_coeff = conductance / area; ///< W/(m^2*K)
inline constexpr Dimension specific_heat = capacity / mass;          ///< J/(kg*K)
inline constexpr Dimension density = mass / (area * length);         ///< kg/m^3
} // namespace dim

/// A parsed unit: the SI value of x [unit] is scale * x + offset.
struct Unit {
  double scale = 1.0;  ///< multiplier to SI
  double offset = 0.0; ///< additive offset to SI (non-zero only for a lone degC or degF)
  Dimension dim;       ///< dimension of the unit
};

/// A unit text that cannot be parsed; offset is the byte inside the text where it went wrong.
struct UnitError : std::runtime_error {
  /// Builds the error with a message and the offset of the offending character.
  UnitError(const std::string& msg, std::size_t off) : std::runtime_error(msg), offset(off) {}
  std::size_t offset; ///< byte offset inside the unit text
};

/// Parses a unit expression ("mm", "W/(m^2*K)", "J/(kg*K)", "degC", "1/s"); throws UnitError.
Unit parse_unit(std::string_view text);

/// Human-readable name of a dimension, preferring engineering forms ("W/K", "J/K", "m^2",
/// "W/(m*K)").
std::string describe(const Dimension& d);

/// Every unit symbol the table knows (without prefixes), for suggestions.
const std::vector<std::string>& known_unit_symbols();

} // namespace thermnet::lang
