// The one entry point of an FMU's binary that is not the standard's: the
// modelDescription.xml of the model in a resources/ folder, which `monohydra
// fmu` asks the staged binary for, so the description comes from the code
// that will run it and the two cannot disagree.
#include <cstring>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "fmu_describe.h"
#include "fmu_export.hpp"
#include "model_description.hpp"
#include "packed_model.hpp"

namespace {

int fail(char* message, size_t capacity, const std::string& why) {
  if (message != nullptr && capacity > 0) {
    std::strncpy(message, why.c_str(), capacity - 1);
    message[capacity - 1] = '\0';
  }
  return 1;
}

}  // namespace

extern "C" MH_FMU_EXPORT int mh_fmu_describe(const char* resources_dir, int fmi_version,
                                             const char* model_identifier,
                                             const char* generation_tool, const char* xml_path,
                                             char* message, size_t capacity) {
  mhs_simulation* sim = nullptr;
  try {
    if (resources_dir == nullptr || model_identifier == nullptr || xml_path == nullptr)
      return fail(message, capacity, "mh_fmu_describe: a NULL argument");
    if (fmi_version != 2 && fmi_version != 3)
      return fail(message, capacity,
                  "the FMI version is 2 or 3, not " + std::to_string(fmi_version));
    const mh::fmu::PackedModel packed = mh::fmu::read_packed_model(resources_dir);
    const std::vector<mhs_setting> settings = mh::fmu::api_settings(packed);
    if (mhs_open_file(packed.model_path.c_str(), settings.data(), settings.size(), &sim) >=
        MHS_ERROR) {
      const std::string why = sim != nullptr ? mhs_message(sim) : "out of memory";
      mhs_free(sim);
      return fail(message, capacity, why);
    }
    mh::fmu::Description d;
    d.fmi_version = fmi_version;
    d.model_identifier = model_identifier;
    d.generation_tool = generation_tool != nullptr ? generation_tool : "monohydra";
    d.token = packed.token;
    mhs_time(sim, nullptr, nullptr, &d.dt, &d.t_end);
    if (mhs_start(sim) >= MHS_ERROR) {
      const std::string why = mhs_message(sim);
      mhs_free(sim);
      return fail(message, capacity, why);
    }
    d.variables = mh::fmu::variable_table(sim, packed.model_text);
    mhs_free(sim);
    sim = nullptr;
    d.model_name = model_identifier;
    std::ofstream out(xml_path, std::ios::binary);
    out << mh::fmu::model_description_xml(d);
    if (!out.flush()) return fail(message, capacity, std::string("cannot write ") + xml_path);
    return 0;
  } catch (const std::exception& e) {
    mhs_free(sim);
    return fail(message, capacity, e.what());
  }
}
