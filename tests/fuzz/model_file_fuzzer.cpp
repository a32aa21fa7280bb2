// libFuzzer target for the model loader: any text must either load or give an
// InputError. Anything else (another exception, a crash, a sanitizer report,
// a hang) is a bug; .ci/fuzz runs it, seeded from models/*.yaml.
#include <cstddef>
#include <cstdint>
#include <string>

#include "monohydra/core/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    mh::parse_model_text(text, "fuzz.yaml");
  } catch (const mh::InputError&) {
    // The expected way to refuse a bad model.
  }
  return 0;
}
