// A shared library that is not a thermnet plugin (no THERMNET_PLUGIN entry points).
extern "C" int some_function() {
  return 42;
}
