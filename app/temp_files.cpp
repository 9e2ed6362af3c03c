#include "app/temp_files.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <mutex>
#include <unistd.h>

namespace thermnet::app {
namespace {

/// Most temporary files at once (a run stages a few outputs; calibrate -o a few model copies).
constexpr std::size_t kSlots = 64;

/// One registered path. `state` says whether `path` may be read by the handler: the path is
/// written before the slot becomes `active` and the slot is freed before it can be rewritten, so
/// the handler never reads a path being written.
struct Slot {
  enum : int { free = 0, writing = 1, active = 2 };
  std::atomic<int> state{free};
  std::array<char, PATH_MAX> path{};
};

std::array<Slot, kSlots> g_slots;
static_assert(std::atomic<int>::is_always_lock_free, "slot states are read in a signal handler");

extern "C" void remove_temp_files_and_reraise(int sig) {
  const int saved = errno;
  for (Slot& s : g_slots)
    if (s.state.load() == Slot::active) ::unlink(s.path.data());
  errno = saved;
  // SA_RESETHAND restored the default action; raising again ends the process by this signal.
  ::raise(sig);
}

void install(int sig) {
  struct sigaction old {};
  if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) return;
  struct sigaction sa {};
  sa.sa_handler = remove_temp_files_and_reraise;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  ::sigaction(sig, &sa, nullptr);
}

} // namespace

void install_temp_file_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGTERM, SIGINT, SIGHUP, SIGPIPE})
      install(sig);
  });
}

int register_temp_file(const std::string& path) {
  if (path.size() >= PATH_MAX) return -1;
  for (std::size_t i = 0; i < g_slots.size(); ++i) {
    int expected = Slot::free;
    if (!g_slots[i].state.compare_exchange_strong(expected, Slot::writing)) continue;
    std::memcpy(g_slots[i].path.data(), path.c_str(), path.size() + 1);
    g_slots[i].state.store(Slot::active);
    return static_cast<int>(i);
  }
  return -1;
}

void unregister_temp_file(int slot) {
  if (slot >= 0 && static_cast<std::size_t>(slot) < g_slots.size())
    g_slots[static_cast<std::size_t>(slot)].state.store(Slot::free);
}

int registered_temp_files() {
  int n = 0;
  for (const Slot& s : g_slots)
    n += s.state.load() == Slot::active ? 1 : 0;
  return n;
}

} // namespace thermnet::app
