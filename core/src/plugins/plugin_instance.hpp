// Thin owners of the plugin instances of a run: a copy of the instance's ops
// table read through the versioning rule (abi_struct.hpp), and the instance
// destroyed exactly once, also when a Simulation's construction throws
// half-way. Statuses a plugin returns pass through status_ok(): a value
// outside the enum is an error, not a success.
#pragma once

#include <utility>

#include "monohydra/core/plugin_call.hpp"
#include "monohydra/monohydra.h"
#include "plugins/abi_struct.hpp"

namespace mh {

// MH_OK and MH_WARNING: the call did its work. Anything else, including a
// value outside the enum, did not.
inline bool status_ok(mh_status s) {
  const int v = static_cast<int>(s);
  return v == MH_OK || v == MH_WARNING;
}
// A plugin's status as one of the enum's values (outside it: MH_ERROR).
inline mh_status normalized(mh_status s) {
  const int v = static_cast<int>(s);
  return v >= MH_OK && v <= MH_FATAL ? s : MH_ERROR;
}

template <class Table>
class PluginInstance {
 public:
  PluginInstance() = default;
  explicit PluginInstance(const Table* instance) : self(instance), ops(read_struct(instance)) {}
  ~PluginInstance() { reset(); }
  PluginInstance(const PluginInstance&) = delete;
  PluginInstance& operator=(const PluginInstance&) = delete;
  PluginInstance(PluginInstance&& o) noexcept
      : self(o.self), ops(o.ops), destroy_site(o.destroy_site) {
    o.self = nullptr;
  }
  PluginInstance& operator=(PluginInstance&& o) noexcept {
    if (this != &o) {
      reset();
      self = std::exchange(o.self, nullptr);
      ops = o.ops;
      destroy_site = o.destroy_site;
    }
    return *this;
  }
  // Destroys the instance, its destroy marked as in flight (plugin_call.hpp)
  // when a site is set: a crash there is named like any other call's.
  void reset() {
    if (self != nullptr && ops.destroy != nullptr) {
      if (destroy_site != nullptr) {
        const PluginCallScope scope(*destroy_site);
        ops.destroy(self);
      } else {
        ops.destroy(self);
      }
    }
    self = nullptr;
  }
  explicit operator bool() const { return self != nullptr; }

  const Table* self = nullptr;  // the plugin's pointer: passed back as every call's first argument
  Table ops{};                  // its operations, up to the plugin's struct_size
  const PluginCallSite* destroy_site = nullptr;  // owned by the instance's host, which outlives it
};

using FormulationProxy = PluginInstance<mh_formulation>;
using SubsystemProxy = PluginInstance<mh_subsystem>;
using IntegratorProxy = PluginInstance<mh_integrator>;

}  // namespace mh
