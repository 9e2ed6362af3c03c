#include "app/command_line.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <string_view>
#include <vector>

namespace thermnet::app {
namespace {

std::vector<std::string>& arguments() {
  static std::vector<std::string> args;
  return args;
}

/// One argument as a POSIX shell reads it back: bare when it holds only safe characters, in
/// single quotes otherwise.
std::string shell_quote(std::string_view a) {
  constexpr std::string_view safe = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                    "0123456789-_./=,:+@%";
  if (!a.empty() && a.find_first_not_of(safe) == std::string_view::npos) return std::string(a);
  std::string q = "'";
  for (const char c : a)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

} // namespace

void remember_command_line(int argc, char** argv) {
  auto& args = arguments();
  args.clear();
  for (int i = 0; i < argc; ++i)
    args.emplace_back(argv[i]);
}

std::string command_line() {
  const auto& args = arguments();
  if (args.empty()) return "thermnet";
  // The program as the user knows it, not the path it was started by.
  std::string s = "thermnet";
  for (std::size_t i = 1; i < args.size(); ++i)
    s += " " + shell_quote(args[i]);
  return s;
}

std::string report_date() {
  std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH"); epoch && *epoch) {
    char* end = nullptr;
    const long long v = std::strtoll(epoch, &end, 10);
    if (end && *end == '\0' && v >= 0) t = static_cast<std::time_t>(v);
  }
  std::tm utc{};
  gmtime_r(&t, &utc);
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02} UTC", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min);
}

} // namespace thermnet::app
