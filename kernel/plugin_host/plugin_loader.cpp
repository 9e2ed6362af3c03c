#include "kernel/plugin_host/plugin_loader.hpp"

#include "kernel/calibration/optimizer.hpp"
#include "kernel/diagnosis/hypothesis.hpp"
#include "kernel/estimation/estimator.hpp"
#include "kernel/plugin_host/plugin_api.hpp"

#include <fmt/format.h>

#include <dlfcn.h>

#include <exception>
#include <filesystem>
#include <system_error>
#include <type_traits>

namespace thermnet {
namespace {

/// Collects what a plugin's registration function contributes, one list per family.
class Collector final : public PluginRegistrar {
public:
  void add_element(ElementPlugin p) override { elements.push_back(std::move(p)); }
  void add_optimizer(OptimizerPlugin p) override { optimizers.push_back(std::move(p)); }
  void add_estimator(EstimatorPlugin p) override { estimators.push_back(std::move(p)); }
  void add_hypothesis(HypothesisPlugin p) override { hypotheses.push_back(std::move(p)); }
  /// Calls fn(list) for the list of every family.
  template <class Fn> void each_family(Fn&& fn) {
    fn(elements);
    fn(optimizers);
    fn(estimators);
    fn(hypotheses);
  }
  std::vector<ElementPlugin> elements;
  std::vector<OptimizerPlugin> optimizers;
  std::vector<EstimatorPlugin> estimators;
  std::vector<HypothesisPlugin> hypotheses;
};

/// Number of kinds in all global registries (to notice static registrars run by dlopen).
std::size_t registered_count() {
  return ElementRegistry::global().names().size() + OptimizerRegistry::global().names().size() +
         EstimatorRegistry::global().names().size() + HypothesisRegistry::global().names().size();
}

/// Key of a kind in the owner table, e.g. "element conductance".
template <class Plugin> std::string owner_key(const Plugin& p) {
  return fmt::format("{} {}", PluginTraits<Plugin>::family, PluginTraits<Plugin>::name(p));
}

/// Checks the collected kinds among themselves (a scratch registry runs every validation), then
/// against the global registries; returns the first problem.
std::optional<std::string> validate(Collector& c, const std::map<std::string, std::string>& owner) {
  std::optional<std::string> problem;
  std::size_t kinds = 0;
  try {
    c.each_family([&](const auto& plugins) {
      using Plugin = typename std::decay_t<decltype(plugins)>::value_type;
      Registry<Plugin> scratch;
      for (const auto& p : plugins) {
        scratch.add(p);
        ++kinds;
        if (!problem && Registry<Plugin>::global().find(PluginTraits<Plugin>::name(p))) {
          auto it = owner.find(owner_key(p));
          problem = fmt::format("its {} kind '{}' is already registered by {}",
                                PluginTraits<Plugin>::family, PluginTraits<Plugin>::name(p),
                                it == owner.end() ? std::string("thermnet itself (a core kind)")
                                                  : "the plugin " + it->second);
        }
      }
    });
  } catch (const std::exception& e) {
    return fmt::format("its kinds are invalid: {}", e.what());
  }
  if (problem) return problem;
  if (kinds == 0) return std::string("it registers no kinds");
  return std::nullopt;
}

} // namespace

PluginLoader& PluginLoader::global() {
  static PluginLoader loader;
  return loader;
}

std::vector<std::string> PluginLoader::loaded() const {
  std::lock_guard lock(mutex_);
  return loaded_;
}

std::optional<std::string> PluginLoader::load(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p(path);
  if (!fs::exists(p, ec)) return std::string("no such file");
  if (fs::is_directory(p, ec)) return std::string("it is a directory, not a shared library");
  // dlopen of a FIFO or a device would block or read forever.
  if (!fs::is_regular_file(p, ec)) return std::string("it is not a regular file");
  fs::path canonical = fs::canonical(p, ec);
  if (ec) return fmt::format("cannot resolve the path: {}", ec.message());
  std::lock_guard lock(mutex_);
  for (const auto& l : loaded_)
    if (l == canonical.string()) return std::nullopt; // already loaded: nothing to do
  return load_locked(canonical.string());
}

std::optional<std::string> PluginLoader::load_locked(const std::string& lib) {
  const std::size_t before = registered_count();
  ::dlerror();
  void* handle = ::dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    return fmt::format("it is not a loadable shared library: {}", why ? why : "dlopen failed");
  }
  if (registered_count() != before)
    return std::string("it registered kinds while being loaded (a static THERMNET_REGISTER_* "
                       "registrar); plugins must register through THERMNET_PLUGIN");
  // From here on, failures unload the library again: nothing of it is referenced.
  auto fail = [handle](std::string message) -> std::optional<std::string> {
    ::dlclose(handle);
    return message;
  };
  using AbiFn = int (*)();
  using RegisterFn = void (*)(PluginRegistrar&);
  auto abi = reinterpret_cast<AbiFn>(::dlsym(handle, THERMNET_PLUGIN_ABI_SYMBOL));
  if (!abi)
    return fail("it is not a thermnet plugin: it exports no thermnet_plugin_abi() (define its "
                "entry points with THERMNET_PLUGIN)");
  if (const int version = abi(); version != THERMNET_PLUGIN_ABI)
    return fail(fmt::format("it was built for plugin ABI {}, but this thermnet has plugin ABI {}; "
                            "rebuild it against this thermnet",
                            version, THERMNET_PLUGIN_ABI));
  auto reg = reinterpret_cast<RegisterFn>(::dlsym(handle, THERMNET_PLUGIN_REGISTER_SYMBOL));
  if (!reg) return fail("it exports thermnet_plugin_abi() but no thermnet_plugin_register()");
  std::optional<std::string> problem;
  {
    Collector c;
    try {
      reg(c);
    } catch (const std::exception& e) {
      problem = fmt::format("its registration failed: {}", e.what());
    } catch (...) {
      problem = std::string("its registration failed with an unknown exception");
    }
    if (!problem) problem = validate(c, owner_);
    if (!problem) {
      c.each_family([&](auto& plugins) {
        for (auto& p : plugins) {
          owner_[owner_key(p)] = lib;
          using Plugin = std::decay_t<decltype(p)>;
          Registry<Plugin>::global().add(std::move(p));
        }
      });
    }
  } // the collected kinds (code of the library) are gone before a failed library is closed
  if (problem) return fail(*problem);
  loaded_.push_back(lib);
  return std::nullopt;
}

} // namespace thermnet
