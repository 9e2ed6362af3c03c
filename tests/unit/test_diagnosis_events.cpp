// Unit tests of the known events of `thermnet diagnose --events`: the file's format and its
// row/column errors, the schedule of an event in a case, and the `switched_conductance` element
// that writes an event loss, against the closed-form cooling of one node through it.
#include "kernel/core/network.hpp"
#include "kernel/core/simulation.hpp"
#include "kernel/diagnosis/events.hpp"
#include "lang/csv.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "loaded_model.hpp"
#include "temp_dir.hpp"

namespace {

using namespace thermnet;

const std::vector<std::string> kCases = {"slow", "pulse"};

/// The message of the CsvError that parsing `text` throws ("" when it parses).
std::string error_of(const std::string& text) {
  try {
    parse_events(text, "ev.csv", kCases);
  } catch (const lang::CsvError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("events file: per-case and every-case windows, columns in any order") {
  const auto ev = parse_events("event,end,start,case\n"
                               "lid,2700,1500,slow\n"
                               "\n"
                               "lid,4200,3000,pulse\n"
                               "lid,7600,7000,\n"
                               "door,100,0,*\n",
                               "ev.csv", kCases);
  REQUIRE(ev.size() == 4);
  CHECK(ev[0].case_name == "slow");
  CHECK(ev[2].case_name.empty());
  CHECK(ev[3].case_name.empty());
  CHECK(event_names(ev) == std::vector<std::string>{"lid", "door"});
  const lang::Signal slow = event_schedule(ev, "slow", "lid");
  CHECK(slow.at(1000) == 0.0);
  CHECK(slow.at(1500) == 1.0);
  CHECK(slow.at(2699) == 1.0);
  CHECK(slow.at(2700) == 0.0);
  CHECK(slow.at(3500) == 0.0); // pulse's window is not slow's
  CHECK(slow.at(7300) == 1.0);
  const lang::Signal every = event_schedule(ev, "", "lid");
  CHECK(every.at(2000) == 0.0);
  CHECK(every.at(7300) == 1.0);
  const lang::Signal door = event_schedule(ev, "pulse", "door"); // on from 0
  CHECK(door.at(0) == 1.0);
  CHECK(door.at(150) == 0.0);
  CHECK(event_schedule(ev, "slow", "fan").is_constant());
}

TEST_CASE("events file: touching windows merge; without an event column the event is 'event'") {
  const auto ev = parse_events("start,end\n0,10\n10,20\n30,40\n", "ev.csv", kCases);
  const lang::Signal s = event_schedule(ev, "slow", "event");
  CHECK(s.times() == std::vector<double>{0, 20, 30, 40});
  CHECK(s.values() == std::vector<double>{1, 0, 1, 0});
}

TEST_CASE("events file: bad input names the file, row and column") {
  CHECK(error_of("case,start\nslow,3\n").starts_with("ev.csv:1: the header must name"));
  CHECK(error_of("case,start,stop\n").starts_with("ev.csv:1:3: unknown column 'stop'"));
  CHECK(error_of("start,end,start\n").starts_with("ev.csv:1:3: column 'start' appears twice"));
  CHECK(error_of("case,start,end\nslow,ten,20\n").starts_with("ev.csv:2:2: 'ten' is not a time"));
  CHECK(error_of("case,start,end\nfast,1,20\n")
            .starts_with("ev.csv:2:1: the model has no case "
                         "'fast' (its cases: slow, pulse)"));
  CHECK(error_of("case,start,end\nslow,30,20\n").starts_with("ev.csv:2:3: end 20 is not after"));
  CHECK(error_of("case,start,end\nslow,-5,20\n").starts_with("ev.csv:2:2: start -5 is negative"));
  CHECK(error_of("case,start,end\nslow,5,20\n,10,30\n")
            .starts_with("ev.csv:3:2: event from 10 to 30 s overlaps its window of row 2"));
  CHECK(error_of("case,start,end\nslow,5\n").starts_with("ev.csv:2: row has 2 fields"));
  CHECK(error_of("case,event,start,end\nslow,lid open,5,9\n")
            .starts_with("ev.csv:2:2: event name 'lid open' must be a name"));
  CHECK(error_of("\n").starts_with("ev.csv:1: the file is empty"));
  CHECK(error_of("start,end\n").find("lists no event") != std::string::npos);
  CHECK(error_of("case,start,end\npulse,5,20\nslow,5,20\n").empty()); // other cases may overlap
}

TEST_CASE("events file: a byte order mark is skipped; overlaps are found in O(n log n)") {
  CHECK(error_of("\xEF\xBB\xBF"
                 "case,start,end\nslow,5,20\n")
            .empty());
  // The first row that overlaps an earlier one is named, with the first such earlier row, as a
  // row-by-row comparison would: every-case windows overlap those of every case.
  CHECK(error_of("case,event,start,end\nslow,lid,50,60\npulse,lid,0,100\nslow,door,55,58\n"
                 ",lid,20,30\n,lid,55,57\n")
            .starts_with("ev.csv:5:3: lid from 20 to 30 s overlaps its window of row 3"));
  CHECK(error_of("case,start,end\nslow,100,200\nslow,0,10\nslow,150,160\nslow,5,6\n")
            .starts_with("ev.csv:4:2: event from 150 to 160 s overlaps its window of row 2"));
  // Every cell is checked before windows are compared: a bad last cell of 100,000 rows of
  // overlapping windows is what is reported.
  std::string text = "start,end\n";
  for (int k = 0; k < 100000; ++k)
    text += fmt::format("{},{}\n", 10 * k, 10 * k + 20);
  text += "5,x\n";
  CHECK(error_of(text).starts_with("ev.csv:100002:2: 'x' is not a time"));
  text.resize(text.size() - 4);
  CHECK(
      error_of(text).starts_with("ev.csv:3:1: event from 10 to 30 s overlaps its window of row 2"));
}

TEST_CASE("events log: the incubator's published log (UNIX ns) placed in the cases by their data") {
  // models/incubator/events.csv: the lid of the third experiment, whose data start at
  // 1611326938.72029 s; the other cases' data start elsewhere or have no UNIX time.
  const auto log = parse_events("time,event\n"
                                "1611327598000000000,\"Lid Opened\"\n"
                                "1611327658000000000,\"Lid Closed\"\n"
                                "1611328159000000000,\"Lid Opened\"\n"
                                "1611328225000000000,\"Lid Closed\"\n",
                                "events.csv", kCases);
  REQUIRE(log.size() == 2);
  CHECK(log[0].absolute);
  CHECK(log[0].event == "lid");
  CHECK(log[1].start == doctest::Approx(1611328159.0));
  const double epoch = 1611326938.72029;
  const auto w = place_events(log,
                              {CaseClock{"slow", 1399, epoch}, CaseClock{"pulse", 1000, 1.5e9},
                               CaseClock{"other", 5000, std::nullopt}},
                              "events.csv");
  REQUIRE(w.size() == 2);
  for (const auto& x : w) {
    CHECK(x.case_name == "slow");
    CHECK_FALSE(x.absolute);
  }
  CHECK(w[0].start == doctest::Approx(659.27971));
  CHECK(w[0].end == doctest::Approx(719.27971));
  CHECK(w[1].start == doctest::Approx(1220.27971));
  CHECK(w[1].end == doctest::Approx(1286.27971));
  const lang::Signal on = event_schedule(w, "slow", "lid");
  CHECK(on.at(700) == 1.0);
  CHECK(on.at(1000) == 0.0);
  CHECK(event_schedule(w, "pulse", "lid").at(700) == 0.0);
  // A log whose times fall in no case says so.
  try {
    place_events(log, {CaseClock{"pulse", 1000, 1.5e9}}, "events.csv");
    FAIL("no error");
  } catch (const lang::CsvError& e) {
    CHECK(std::string(e.what()).find("fall in no case") != std::string::npos);
  }
}

TEST_CASE("events log: times from the start of each case, windows cut to the case") {
  const auto log = parse_events("case,time,event\n"
                                "slow,100,door open\n"
                                "slow,50,heater ON\n" // out of order: sorted
                                "slow,300,door closed\n"
                                "pulse,20,Door 2 stop\n" // off first: on from the start
                                "slow,900,door open\n",  // never closed: on to the end
                                "ev.csv", kCases);
  const auto w =
      place_events(log, {CaseClock{"slow", 1000, {}}, CaseClock{"pulse", 500, {}}}, "ev.csv");
  auto find = [&](const std::string& c, const std::string& ev, double start) {
    for (const auto& x : w)
      if (x.case_name == c && x.event == ev && x.start == start) return x.end;
    return -1.0;
  };
  CHECK(find("slow", "door", 100) == 300);
  CHECK(find("slow", "door", 900) == 1000);
  CHECK(find("slow", "heater", 50) == 1000);
  CHECK(find("pulse", "door_2", 0) == 20);
  CHECK(w.size() == 4);
}

TEST_CASE("events log: bad input names the file, row and column") {
  CHECK(error_of("time,event\n5,lid ajar\n")
            .starts_with("ev.csv:2:2: 'lid ajar' does not end in an on/off word"));
  CHECK(error_of("time,event\n1611327598,lid open\n30,lid closed\n")
            .starts_with("ev.csv:3:1: time 30 is not a UNIX time"));
  CHECK(error_of("time,event\n-3,lid open\n").starts_with("ev.csv:2:1: time -3 is negative"));
  CHECK(error_of("time,start,event\n").starts_with("ev.csv:1:1: a file lists windows"));
  CHECK(error_of("time,case\n").starts_with("ev.csv:1: a log names the columns"));
  CHECK(error_of("case,time,event\nnone,1,lid on\n")
            .starts_with("ev.csv:2:1: the model has no case 'none'"));
}

TEST_CASE("switched_conductance: a node cools through it only while it is on (closed form)") {
  // C dT/dt = -G on(t) (T - Tb): constant while off, exp(-G t / C) towards Tb while on.
  test::TempDir dir;
  const std::string path =
      dir.write("m.tnet", "boundary cold T = 0\n"
                          "node a C = 1000 [J/K] T0 = 50\n"
                          "switched_conductance lid a cold G = 2 [W/K] on = step(0: 0, 600: 1, "
                          "1100: 0)\n"
                          "case run { duration = 2000; output = 50 }\n");
  test::LoadedModel m(path, test::Lint::clean);
  Network net(m.model->instantiate("run"));
  const SimulationResult r = simulate(net);
  const auto at = [&](double t) {
    for (std::size_t k = 0; k < r.times.size(); ++k)
      if (std::abs(r.times[k] - t) < 1e-9)
        return r.temps[k][static_cast<std::size_t>(net.spec().node_index("a"))];
    FAIL("no output at ", t);
    return 0.0;
  };
  const double T0 = 323.15, Tb = 273.15, rate = 2.0 / 1000.0;
  CHECK(at(500) == doctest::Approx(T0).epsilon(1e-6));
  CHECK(at(900) == doctest::Approx(Tb + (T0 - Tb) * std::exp(-rate * 300)).epsilon(1e-5));
  const double closed = Tb + (T0 - Tb) * std::exp(-rate * 500);
  CHECK(at(1100) == doctest::Approx(closed).epsilon(1e-5));
  CHECK(at(2000) == doctest::Approx(closed).epsilon(1e-5)); // off again: no more loss
}

} // namespace
