// A plugin built for another plugin ABI: its registration must never run.
#include "kernel/plugin_host/plugin_api.hpp"

#include <cstdlib>

extern "C" __attribute__((visibility("default"))) int thermnet_plugin_abi() {
  return THERMNET_PLUGIN_ABI + 1000;
}
extern "C" __attribute__((visibility("default"))) void
thermnet_plugin_register(thermnet::PluginRegistrar&) {
  std::abort(); // the loader must refuse the library before calling this
}
