// Inputs tests/fuzz found that once hung or crashed the model loader; each
// must now give an InputError with the file and what was expected.
#include <gtest/gtest.h>

#include <string>

#include "monohydra/core/model_file.hpp"

namespace mh {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_model_text(text, "fuzz.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// yaml-cpp's LoadAll looped forever on a top-level ',' (empty documents
// without end, 2 GB in 10 s); the fuzzer's input, minimized to 48 bytes.
TEST(ModelFileFuzzRegressions, StrayTopLevelCommaIsAnErrorNotAHang) {
  EXPECT_EQ(error_of(",\n"),
            "fuzz.yaml:1:1: expected a mapping with the model (units, bodies, ...), got nothing");
  EXPECT_EQ(error_of(std::string("# A planarm:\n  , axis: [\0\0 far end\n    mass: 1.0", 48)),
            "fuzz.yaml:2:3: expected a mapping with the model (units, bodies, ...), got nothing");
}

TEST(ModelFileFuzzRegressions, SecondDocumentIsStillRefusedAtItsLine) {
  EXPECT_EQ(error_of("units: {}\n---\nunits: {}\n"),
            "fuzz.yaml:3:1: expected a single YAML document, found more than one");
}

}  // namespace
}  // namespace mh
