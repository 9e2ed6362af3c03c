// The language front end on one model: the time and memory of each stage a command goes through
// before it simulates — reading and parsing the files with loops and instances expanded
// (Model::load), checking every case (lint), elaborating the case (network), and building the
// kernel's Network — and their rate in MB of model text per second.
//
// Usage: thermnet_bench_front_end [--no-prefault] MODEL.tnet [CASE]
// --no-prefault leaves every page to the loading thread, so the peak RSS is what the front end
// touches by itself: the basis of the prefault size in app/huge_page_heap.cpp.
// Prints one line per stage (wall and CPU seconds, peak RSS so far) and a summary line
// `front end: N MB in W s wall (R MB/s), peak RSS P MB (X times the file)` read by bench/run.py.
// The heap is set up as `thermnet` sets it up (app/huge_page_heap.hpp).

#include "app/huge_page_heap.hpp"
#include "kernel/core/element_registry.hpp"
#include "kernel/core/network.hpp"
#include "lang/model.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <sys/resource.h>
#include <utility>

using namespace thermnet;

namespace {

double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// User + system CPU seconds of the process so far.
double cpu_now() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// Peak resident set size of the process so far, in MB.
double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

} // namespace

int main(int argc, char** argv) {
  thermnet::app::reserve_huge_page_heap(std::size_t{1} << 30);
  const bool prefault = !(argc > 1 && std::string_view(argv[1]) == "--no-prefault");
  if (!prefault) --argc, ++argv;
  if (argc < 2) {
    std::fprintf(stderr, "usage: thermnet_bench_front_end [--no-prefault] MODEL.tnet [CASE]\n");
    return 2;
  }
  const std::string path = argv[1];
  const std::string case_name = argc > 2 ? argv[2] : "";
  const auto bytes = std::filesystem::file_size(path);
  const double mb = static_cast<double>(bytes) / 1e6;
  if (prefault) thermnet::app::prefault_heap_for(bytes); // as app/model_loading.cpp does
  const double w0 = wall_now(), c0 = cpu_now();
  double w = w0, c = c0;
  auto stage = [&](const char* name) {
    const double w1 = wall_now(), c1 = cpu_now();
    std::printf("%-8s %7.3f s wall %7.3f s cpu   peak RSS %7.1f MB\n", name, w1 - w, c1 - c,
                peak_rss_mb());
    w = w1;
    c = c1;
  };
  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  auto model = lang::Model::load(path, element_catalog(), sources, diags);
  if (!model) {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    return 2;
  }
  stage("load");
  model->lint(diags);
  stage("lint");
  if (diags.error_count() > 0) {
    std::fprintf(stderr, "%s has %zu errors\n", path.c_str(), diags.error_count());
    return 1;
  }
  // As `simulate` does: the case's network moves out of the model's cache into the Network.
  lang::NetworkSpec spec = model->take_network(case_name);
  stage("network");
  Network net(std::move(spec));
  stage("build");
  const double total = wall_now() - w0, peak = peak_rss_mb();
  std::printf("front end: %.1f MB in %.3f s wall, %.3f s cpu (%.1f MB/s), peak RSS %.0f MB (%.1f "
              "times the file), %d unknowns\n",
              mb, total, cpu_now() - c0, mb / total, peak, peak / mb, net.size());
  return 0;
}
