/* monohydra SDK: the one symbol a plugin library exports.
 *
 *   MH_PLUGIN_EXPORT const mh_plugin_entry mh_entry = { ... };
 *
 * The host checks abi_version.major against its own (a plugin of another major
 * version is refused, naming both), calls init once, asks get_factory for
 * MH_FORMULATION_FACTORY_ID, MH_SUBSYSTEM_FACTORY_ID and
 * MH_INTEGRATOR_FACTORY_ID, and calls deinit once before unloading. Factories live as long as the
 * library. */
#ifndef MONOHYDRA_ENTRY_H
#define MONOHYDRA_ENTRY_H

#include "monohydra/types.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define MH_PLUGIN_EXPORT __declspec(dllexport)
#else
#define MH_PLUGIN_EXPORT __attribute__((visibility("default")))
#endif

#define MH_ENTRY_SYMBOL "mh_entry"

typedef struct mh_plugin_entry {
  mh_version abi_version; /* MH_ABI_VERSION_INIT of the SDK the plugin was built with */
  /* Returns 0 on failure (the library is then not used). plugin_path is the
   * library's own file. */
  int (*init)(const char* plugin_path);
  void (*deinit)(void);
  /* The factory for a factory id, or NULL. */
  const void* (*get_factory)(const char* factory_id);
} mh_plugin_entry;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_ENTRY_H */
