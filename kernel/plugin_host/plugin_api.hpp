#pragma once
/// The public interface of out-of-tree plugins: the ABI version and the THERMNET_PLUGIN entry
/// point.
///
/// A plugin is a shared library that defines its kinds with THERMNET_PLUGIN instead of the static
/// THERMNET_REGISTER_* registrars: the host dlopens it, checks thermnet_plugin_abi() and only then
/// calls thermnet_plugin_register(), so nothing of a mismatched plugin runs against the registries.

#include "kernel/core/element_registry.hpp"

/// Version of the plugin ABI: bumped whenever a type a plugin sees (ElementPlugin, Element,
/// ElementSchema, OptimizerPlugin, EstimatorPlugin, HypothesisPlugin, ...) changes layout or
/// meaning. 2: hypotheses join the plugin families; one Registry template. 3: Hypothesis gains
/// mechanisms(), recalibrates() and rewrites(). 4: ElementSpec::values is a KeySignals (a sorted
/// flat list with a map's interface) instead of a std::map. 5: ElementSpec is laid out for big
/// networks (kind(), nodes(), composite(), parts() are accessors; key names are string_views of
/// the schema's), Signal::kind() is an accessor, NodeSpec::doc() an accessor.
#define THERMNET_PLUGIN_ABI 5

namespace thermnet {

struct OptimizerPlugin;
struct EstimatorPlugin;
struct HypothesisPlugin;

/// What a plugin's registration function receives: it collects kinds, which the loader adds to the
/// global registries once all of them proved valid and new.
class PluginRegistrar {
public:
  /// Contributes an element kind.
  virtual void add_element(ElementPlugin plugin) = 0;
  /// Contributes an optimizer kind (include kernel/calibration/optimizer.hpp).
  virtual void add_optimizer(OptimizerPlugin plugin) = 0;
  /// Contributes an estimator kind (include kernel/estimation/estimator.hpp).
  virtual void add_estimator(EstimatorPlugin plugin) = 0;
  /// Contributes a diagnosis hypothesis kind (include kernel/diagnosis/hypothesis.hpp).
  virtual void add_hypothesis(HypothesisPlugin plugin) = 0;

protected:
  ~PluginRegistrar() = default;
};

} // namespace thermnet

/// Name of the ABI function every plugin exports (`extern "C" int thermnet_plugin_abi()`).
#define THERMNET_PLUGIN_ABI_SYMBOL "thermnet_plugin_abi"
/// Name of the registration function every plugin exports.
#define THERMNET_PLUGIN_REGISTER_SYMBOL "thermnet_plugin_register"

/// Defines a plugin's entry points; the body that follows registers its kinds through REGISTRAR:
///
///     THERMNET_PLUGIN(registrar) { registrar.add_element(make_peltier()); }
#define THERMNET_PLUGIN(REGISTRAR)                                                                 \
  extern "C" __attribute__((visibility("default"))) int thermnet_plugin_abi() {                    \
    return THERMNET_PLUGIN_ABI;                                                                    \
  }                                                                                                \
  extern "C" __attribute__((visibility("default"))) void thermnet_plugin_register(                 \
      ::thermnet::PluginRegistrar& REGISTRAR)
