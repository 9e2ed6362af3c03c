#include "import/sinda_units.hpp"

#include <fmt/format.h>

#include <cmath>

namespace thermnet::importer::sinda {

namespace {

constexpr double btu = 1055.05585262;                   // J, International Table BTU
constexpr double btu_per_degF = btu * 1.8;              // J/K
constexpr double btu_per_hr_degF = btu_per_degF / 3600; // W/K
constexpr double btu_per_hr = btu / 3600;               // W
constexpr double sigma_si = 5.670374419e-8;             // W/(m^2 K^4), thermnet's sigma

bool near(double a, double b, double tol) {
  return std::fabs(a - b) <= tol;
}

std::string format_control(double v) {
  return number_text(v);
}

} // namespace

Units::Units(const Deck& deck, const ConductorCard* radiation, Report& report) {
  const Control& c = deck.control;
  if (!c.uid && !c.abszro) {
    if (radiation != nullptr) {
      report.error(radiation->at, "missing-units",
                   "a radiation conductor needs the deck's units: give UID, ABSZRO and SIGMA in "
                   "HEADER CONTROL DATA, GLOBAL (e.g. UID = SI, ABSZRO = -273.15, SIGMA = "
                   "5.670374419E-8)");
      return;
    }
    // (at the control data that lacks them, else at the deck's first block)
    report.note(c.at ? c.at : deck.first_header,
                "the deck states no units (neither UID nor ABSZRO in CONTROL DATA, GLOBAL): its "
                "numbers are read as SI (J/K, W/K, W, s) and its temperatures as degC; without "
                "radiation the temperatures equal SINDA's whatever units the deck meant");
    return;
  }
  if (c.uid)
    eng_ = *c.uid == "ENG";
  else
    eng_ = c.abszro->value < -400;
  if (c.abszro) {
    const double a = c.abszro->value;
    abszro_ = a;
    if (!eng_ && a == 0)
      scale_ = Scale::kelvin;
    else if (!eng_ && near(a, -273.15, 1e-9))
      scale_ = Scale::celsius;
    else if (!eng_ && near(a, -273.15, 1.0))
      scale_ = Scale::absolute_k;
    else if (eng_ && a == 0)
      scale_ = Scale::rankine;
    else if (eng_ && near(a, -459.67, 1e-9))
      scale_ = Scale::fahrenheit;
    else if (eng_ && near(a, -459.67, 1.0))
      scale_ = Scale::absolute_r;
    else {
      report.error(
          c.abszro->at, "invalid-value",
          fmt::format("ABSZRO = {} does not fit UID = {}: expected {}", format_control(a),
                      eng_ ? "ENG" : "SI",
                      eng_ ? "-459.67 or -460 (degF) or 0 (degR)" : "-273.15 (degC) or 0 (K)"));
      return;
    }
    if (scale_ == Scale::absolute_k || scale_ == Scale::absolute_r)
      report.note(c.abszro->at,
                  fmt::format("ABSZRO = {}: temperatures are written as absolute temperatures "
                              "(T - ABSZRO, in {}), so that radiation sees the absolute "
                              "temperatures SINDA computes with; thermnet's {} has its zero at {}",
                              format_control(a), eng_ ? "degR" : "K", eng_ ? "degF" : "degC",
                              eng_ ? "-459.67" : "-273.15"));
  } else {
    scale_ = eng_ ? Scale::fahrenheit : Scale::celsius;
    abszro_ = eng_ ? -459.67 : -273.15;
    if (radiation != nullptr) {
      report.error(radiation->at, "missing-units",
                   "a radiation conductor needs ABSZRO in HEADER CONTROL DATA, GLOBAL: the "
                   "absolute temperatures SIGMA multiplies depend on it");
      return;
    }
    report.note(c.uid_at, fmt::format("ABSZRO is not given: temperatures are read as {}",
                                      eng_ ? "degF" : "degC"));
  }
  if (radiation == nullptr) return;
  if (!c.sigma) {
    report.error(radiation->at, "missing-units",
                 fmt::format("a radiation conductor needs SIGMA in HEADER CONTROL DATA, GLOBAL: "
                             "SIGMA = {} if the deck's G values are areas times exchange factors "
                             "({}), SIGMA = 1.0 if they include the Stefan-Boltzmann constant",
                             eng_ ? "0.1714E-8" : "5.670374419E-8", eng_ ? "ft^2" : "m^2"));
    return;
  }
  if (!(c.sigma->value > 0)) {
    report.error(c.sigma->at, "invalid-value",
                 fmt::format("SIGMA must be positive, got {}", format_control(c.sigma->value)));
    return;
  }
  sigma_ = c.sigma;
  rad_unit_ = c.sigma->value * (eng_ ? btu_per_hr * std::pow(1.8, 4) : 1.0) / sigma_si;
  sigma_place_ = place_text(report.sources(), c.sigma->at);
}

Value Units::temperature(double T, lang::Span at) const {
  const double absolute = T - abszro_;
  if (absolute < 0)
    throw ImportError(at, "invalid-value",
                      fmt::format("temperature {} lies below absolute zero (ABSZRO = {})",
                                  number_text(T), format_control(abszro_)));
  switch (scale_) {
  case Scale::celsius:
    return {number_text(T), T + 273.15};
  case Scale::kelvin:
    return {number_text(T) + " [K]", T};
  case Scale::fahrenheit:
    return {number_text(T) + " [degF]", (T + 459.67) / 1.8};
  case Scale::rankine:
    return {number_text(T) + " [degR]", T / 1.8};
  case Scale::absolute_k:
    return {number_text(absolute) + " [K]", absolute};
  case Scale::absolute_r:
    return {number_text(absolute) + " [degR]", absolute / 1.8};
  }
  return {};
}

Value Units::capacity(double C) const {
  if (C == 0 || !eng_) return {number_text(C), eng_ ? C * btu_per_degF : C};
  used_C_ = true;
  return {number_text(C) + " * C_unit", C * btu_per_degF};
}

Value Units::conductance(double G) const {
  if (!eng_) return {number_text(G), G};
  used_G_ = true;
  return {number_text(G) + " * G_unit", G * btu_per_hr_degF};
}

Value Units::radiation(double G) const {
  used_rad_ = true;
  return {number_text(G) + " * rad_unit", G * rad_unit_};
}

Value Units::power(const std::vector<double>& terms) const {
  std::string text;
  double sum = 0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const double t = terms[i];
    sum += t;
    if (i == 0)
      text = number_text(t);
    else
      text += (t < 0 ? " - " : " + ") + number_text(std::fabs(t));
  }
  if (!eng_) return {text, sum};
  used_P_ = true;
  return {(terms.size() > 1 ? "(" + text + ")" : text) + " * P_unit", sum * btu_per_hr};
}

Value Units::time(double t) const {
  if (!eng_) return {number_text(t), t};
  return {number_text(t) + " [h]", t * 3600};
}

std::vector<Const> Units::consts() const {
  std::vector<Const> out;
  if (used_C_)
    out.push_back({"C_unit", number_text(btu_per_degF) + " [J/K]", "1 BTU/degF (UID = ENG)"});
  if (used_G_)
    out.push_back(
        {"G_unit", number_text(btu_per_hr_degF) + " [W/K]", "1 BTU/(hr degF) (UID = ENG)"});
  if (used_P_) out.push_back({"P_unit", number_text(btu_per_hr) + " [W]", "1 BTU/hr (UID = ENG)"});
  if (used_rad_ && sigma_)
    out.push_back({"rad_unit", number_text(rad_unit_) + " [m^2]",
                   fmt::format("thermnet's GR per unit of a radiation conductor's G: the deck's "
                               "SIGMA = {} ({}){} over thermnet's sigma",
                               format_control(sigma_->value), sigma_place_,
                               eng_ ? " in BTU/(hr ft^2 degR^4)" : "")});
  return out;
}

std::string Units::description() const {
  const char* t = "degC";
  switch (scale_) {
  case Scale::celsius:
    t = "degC";
    break;
  case Scale::kelvin:
    t = "K";
    break;
  case Scale::fahrenheit:
    t = "degF";
    break;
  case Scale::rankine:
    t = "degR";
    break;
  case Scale::absolute_k:
    t = "K, absolute";
    break;
  case Scale::absolute_r:
    t = "degR, absolute";
    break;
  }
  return fmt::format("Units: UID = {} ({}), ABSZRO = {} (temperatures written in {})",
                     eng_ ? "ENG" : "SI", eng_ ? "BTU, hour, degF, ft" : "J, s, K, m",
                     format_control(abszro_), t);
}

} // namespace thermnet::importer::sinda
