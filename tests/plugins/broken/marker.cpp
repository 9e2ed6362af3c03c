// A shared library whose constructor writes the file named by THERMNET_TEST_MARKER: the marker
// shows that something loaded it (dlopen runs constructors before any check can refuse it).

#include <cstdio>
#include <cstdlib>

namespace {

__attribute__((constructor)) void write_marker() {
  const char* path = std::getenv("THERMNET_TEST_MARKER");
  if (path == nullptr) return;
  if (std::FILE* f = std::fopen(path, "w")) {
    std::fputs("loaded\n", f);
    std::fclose(f);
  }
}

} // namespace
