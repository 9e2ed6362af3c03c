#pragma once
/// The units of a SINDA/FLUINT deck (UID, ABSZRO and SIGMA of its control data) and how its values
/// are written in thermnet: SI decks as bare numbers (degC) or with [K]; ENG decks (BTU, hour,
/// degF, ft) through the consts C_unit, G_unit and P_unit and with [degF], [degR] or [h]; the
/// radiation conductors' G through rad_unit, the deck's SIGMA over thermnet's sigma.

#include "import/network.hpp"
#include "import/report.hpp"
#include "import/sinda_deck.hpp"

#include <optional>
#include <string>
#include <vector>

namespace thermnet::importer::sinda {

/// How a deck's temperatures are written.
enum class Scale {
  celsius,    ///< ABSZRO = -273.15: bare numbers (thermnet's degC)
  kelvin,     ///< ABSZRO = 0 with UID = SI: [K]
  fahrenheit, ///< ABSZRO = -459.67 with UID = ENG: [degF]
  rankine,    ///< ABSZRO = 0 with UID = ENG: [degR]
  absolute_k, ///< another ABSZRO near -273.15: T - ABSZRO written in [K]
  absolute_r  ///< another ABSZRO near -459.67 (SINDA's -460): T - ABSZRO written in [degR]
};

/// The units of a deck and the texts its values are written with.
class Units {
public:
  /// The units the deck's control data give; reports what it had to assume, and errors for
  /// radiation conductors without ABSZRO and SIGMA. `radiation` is the deck's first radiation
  /// conductor, if any.
  Units(const Deck& deck, const ConductorCard* radiation, Report& report);

  /// A temperature (node T, boundary T) at `at`; throws ImportError below absolute zero.
  Value temperature(double T, lang::Span at) const;
  /// A capacitance (C >= 0).
  Value capacity(double C) const;
  /// A linear conductance.
  Value conductance(double G) const;
  /// A radiation conductor's G as thermnet's GR.
  Value radiation(double G) const;
  /// A heat rate: the terms of a node's loads, added.
  Value power(const std::vector<double>& terms) const;
  /// A time (TIMEND, OUTPUT).
  Value time(double t) const;
  /// The consts the values written so far use (only those).
  std::vector<Const> consts() const;
  /// One line saying which units the deck uses, for the model's heading.
  std::string description() const;
  /// True for UID = ENG.
  bool eng() const { return eng_; }

private:
  bool eng_ = false;
  Scale scale_ = Scale::celsius;
  double abszro_ = -273.15;
  std::optional<ControlValue> sigma_;
  std::string sigma_place_;
  double rad_unit_ = 0;
  mutable bool used_C_ = false, used_G_ = false, used_P_ = false, used_rad_ = false;
};

} // namespace thermnet::importer::sinda
