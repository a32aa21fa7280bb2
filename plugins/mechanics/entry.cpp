// The mechanics plugin library: one entry symbol, one subsystem factory that
// lists its components.
#include "monohydra/entry.h"

#include <string>

#include "components.hpp"

namespace {

const mh_component_descriptor* const kComponents[] = {&mech::kSpringDamperDescriptor,
                                                      &mech::kMaxwellDescriptor};

uint32_t count(const mh_subsystem_factory*) {
  return 2;
}
const mh_component_descriptor* descriptor(const mh_subsystem_factory*, uint32_t i) {
  return i < 2 ? kComponents[i] : nullptr;
}
const mh_subsystem* create(const mh_subsystem_factory*, const mh_host* host, const char* id) {
  if (host == nullptr || id == nullptr) return nullptr;
  const std::string name = id;
  if (name == mech::kSpringDamperDescriptor.id) return mech::create_spring_damper(host);
  if (name == mech::kMaxwellDescriptor.id) return mech::create_maxwell_element(host);
  return nullptr;
}

const mh_subsystem_factory kFactory{sizeof(mh_subsystem_factory), count, descriptor, create};

int init(const char*) {
  return 1;
}
void deinit() {}
const void* get_factory(const char* id) {
  return std::string(id) == MH_SUBSYSTEM_FACTORY_ID ? &kFactory : nullptr;
}

}  // namespace

extern "C" MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry{MH_ABI_VERSION_INIT, init, deinit,
                                                           get_factory};
