/* What `monohydra fmu` calls in the binary it packs (describe.cpp). */
#ifndef MONOHYDRA_FMU_DESCRIBE_H
#define MONOHYDRA_FMU_DESCRIBE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Writes the modelDescription.xml (FMI `fmi_version`, 2 or 3) of the model in
 * `resources_dir` to `xml_path`. 0 when written; else 1 and the reason in
 * `message` (NUL-terminated, cut to `capacity`). */
typedef int mh_fmu_describe_fn(const char* resources_dir, int fmi_version,
                               const char* model_identifier, const char* generation_tool,
                               const char* xml_path, char* message, size_t capacity);

#ifdef __cplusplus
}
#endif

#endif
