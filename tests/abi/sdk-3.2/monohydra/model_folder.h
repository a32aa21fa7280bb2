/* monohydra SDK: the folder of the model file, for a component whose option
 * names a file relative to it (an imported FMU: `fmu: plant.fmu`).
 *
 * An optional service (get_service(host, MH_SERVICE_MODEL_FOLDER)): a host
 * that has none returns NULL, and the component then takes a relative path
 * relative to the working directory. Not part of monohydra.h: a plugin that
 * reads no file needs none of it. */
#ifndef MONOHYDRA_MODEL_FOLDER_H
#define MONOHYDRA_MODEL_FOLDER_H

#include "monohydra/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Subsystems, during setup. */
#define MH_SERVICE_MODEL_FOLDER "monohydra.model-folder/1"
typedef struct mh_model_folder_service {
  uint32_t struct_size;
  /* The absolute folder of the model file, without a trailing slash (for a
   * model parsed from text: the folder its caller named, or the working
   * directory). Valid until setup returns: copy what is kept. */
  const char* (*model_folder)(const struct mh_host* host);
} mh_model_folder_service;

#ifdef __cplusplus
}
#endif

#endif /* MONOHYDRA_MODEL_FOLDER_H */
