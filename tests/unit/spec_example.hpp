#pragma once
/// The example model of the language contract (shared/spec/language.md), word for word.

namespace thermnet::test {

/// The spec's two-plate example; its case reads "warmup.csv" next to the model.
inline constexpr const char* spec_example = R"(model two_plates
param h_gap = 4 [W/(m^2*K)] range 1 .. 10 "gas gap convection"
boundary ambient T = pwl(0: 20, 2750: -35)
node plate1 C = 450 [J/K]
node plate2 C = 300 [J/K] T0 = 20
convection gap plate1 plate2 h = h_gap A = 0.02
radiation rad plate1 plate2 A = 0.02 eps1 = 0.85 eps2 = 0.1
series mount plate2 ambient { contact h = 2500 A = 30e-4 ; conduction k = 0.25 L = 3 [mm] A = 54.8 [mm^2] }
heater film plate1 P = 10
case warmup {
  duration = 3 [h]
  film.P = step(0: 10, 2500: 0)
  data "warmup.csv"
}
)";

} // namespace thermnet::test
