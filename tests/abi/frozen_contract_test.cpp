// ABI 3.0 frozen: after 3.0 the SDK only appends (CLAP's rule, types.h). The
// contract list sdk-3.0/contract.def, compiled against the frozen copy of the
// 3.0 headers and against the SDK's own, must agree field by field: a field
// moved, resized or retyped, a struct that shrank, a constant renumbered or a
// struct grown without a new minor fails here, naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "abi/contract_record.h"
#include "build_paths.hpp"
#include "text_file.hpp"

namespace {

using mh::test::read_text;

std::string frozen_dir() {
  return std::string(mh::test::paths::source_dir) + "/tests/abi/sdk-3.0";
}

// The two tables list the same entries in the same order (one list compiled
// twice); the tests below compare them entry by entry.
void expect_same_entries() {
  ASSERT_EQ(mh_abi_frozen_count, mh_abi_current_count);
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    ASSERT_EQ(mh_abi_frozen[i].kind, mh_abi_current[i].kind) << mh_abi_frozen[i].name;
    ASSERT_STREQ(mh_abi_frozen[i].name, mh_abi_current[i].name);
  }
}

std::string label(const mh_abi_record& r) {
  return r.owner != nullptr ? std::string(r.owner) + "." + r.name : std::string(r.name);
}

// The frozen headers, concatenated, without their comments.
std::string frozen_headers_without_comments() {
  std::string all;
  for (const char* name : {"entry.h", "formulation.h", "host.h", "integrator.h", "monohydra.h",
                           "state.h", "subsystem.h", "types.h"})
    all += read_text(frozen_dir() + "/monohydra/" + name) + "\n";
  std::string out;
  for (size_t i = 0; i < all.size(); ++i) {
    if (all.compare(i, 2, "/*") == 0) {
      i = all.find("*/", i + 2) + 1;
    } else if (all.compare(i, 2, "//") == 0) {
      i = all.find('\n', i) - 1;
    } else {
      out += all[i];
    }
  }
  return out;
}

// How many members the definition of `typedef struct NAME { ... }` declares:
// the declarators at the braces' own level (one per ';', one more per ',').
int members_declared(const std::string& text, const std::string& name) {
  const size_t at = text.find("typedef struct " + name + " {");
  if (at == std::string::npos) return -1;
  int braces = 0;
  int parens = 0;
  int members = 0;
  for (size_t i = text.find('{', at); i < text.size(); ++i) {
    const char c = text[i];
    if (c == '{') ++braces;
    if (c == '}' && --braces == 0) break;
    if (c == '(') ++parens;
    if (c == ')') --parens;
    if (braces == 1 && parens == 0 && (c == ';' || c == ',')) ++members;
  }
  return members;
}

uint64_t fnv1a(const std::string& bytes) {
  uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

// A frozen copy's headers (DIR/monohydra/) are exactly those `shipped`
// names, each with its FNV-1a as that minor shipped it: none edited, none
// added or gone.
void expect_as_shipped(const std::string& dir, const std::map<std::string, uint64_t>& shipped) {
  std::set<std::string> present;
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/monohydra"))
    present.insert(entry.path().filename().string());
  std::set<std::string> listed;
  for (const auto& [name, hash] : shipped) {
    listed.insert(name);
    EXPECT_EQ(fnv1a(read_text(dir + "/monohydra/" + name)), hash) << dir << ": " << name;
  }
  EXPECT_EQ(present, listed) << dir;
}

}  // namespace

TEST(FrozenAbi, TheFrozenHeadersAreThreeZero) {
  EXPECT_EQ(mh_abi_frozen_major, 3u);
  EXPECT_EQ(mh_abi_frozen_minor, 0u);
}

// The frozen copy is never edited: a header "fixed" to match a moved field
// would hide the move. FNV-1a of each file as 3.0 shipped it.
TEST(FrozenAbi, TheFrozenHeadersAreTheOnesThreeZeroShipped) {
  const std::map<std::string, uint64_t> shipped = {
      {"entry.h", 0x1a27eb9eff7cdb11ull},     {"formulation.h", 0xb55dbc7564f6bd01ull},
      {"host.h", 0xaf34839a51edd2ebull},      {"integrator.h", 0x6ad1359afa7ee48full},
      {"monohydra.h", 0x7c7a3d39b58b5695ull}, {"state.h", 0xd57a169b283ff7fcull},
      {"subsystem.h", 0xdce196c64bce0ae9ull}, {"types.h", 0x9039a870b9612ccaull},
  };
  expect_as_shipped(frozen_dir(), shipped);
}

// 3.2 is frozen as well (tests/abi/sdk-3.2/: its headers as 3.2 shipped
// them): plugins built against that copy alone are loaded and run by
// frozen_plugins_test.cpp. Never edit the copy.
TEST(FrozenAbi, TheFrozenHeadersAreTheOnesThreeTwoShipped) {
  const std::map<std::string, uint64_t> shipped = {
      {"constrained.h", 0x1f1917f9492c2444ull},  {"entry.h", 0x1a27eb9eff7cdb11ull},
      {"formulation.h", 0x49af3caaff1dd2d0ull},  {"host.h", 0x796da5186aa4a69dull},
      {"integrator.h", 0x6ad1359afa7ee48full},   {"inverse_dynamics.h", 0xc56679fad9010654ull},
      {"model_folder.h", 0x7bb50bb9c6273434ull}, {"monohydra.h", 0x7c7a3d39b58b5695ull},
      {"parameters.h", 0x7d45172a37346802ull},   {"sparsity.h", 0xd15f0dd657192327ull},
      {"state.h", 0xd57a169b283ff7fcull},        {"subsystem.h", 0xdce196c64bce0ae9ull},
      {"types.h", 0x11ef564e47a77c8eull},        {"visual.h", 0xf79e7378ed211111ull},
  };
  expect_as_shipped(std::string(mh::test::paths::source_dir) + "/tests/abi/sdk-3.2", shipped);
}

// The list names every struct, member and constant of the frozen headers, so
// nothing of 3.0 escapes the comparisons below.
TEST(FrozenAbi, TheListHoldsEveryMemberAndConstantOfThreeZero) {
  const std::string text = frozen_headers_without_comments();
  std::map<std::string, int> listed;
  std::vector<std::string> constants;
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& r = mh_abi_frozen[i];
    if (r.kind == MH_ABI_RECORD_STRUCT) listed[r.name] += 0;
    if (r.kind == MH_ABI_RECORD_FIELD) ++listed[r.owner];
    if (r.kind == MH_ABI_RECORD_INTEGER || r.kind == MH_ABI_RECORD_STRING)
      constants.emplace_back(r.name);
  }
  // Every struct the headers define is listed, with all its members.
  size_t structs = 0;
  for (size_t at = text.find("typedef struct "); at != std::string::npos;
       at = text.find("typedef struct ", at + 1)) {
    const size_t name_end = text.find_first_of(" {", at + 15);
    const std::string name = text.substr(at + 15, name_end - at - 15);
    if (text.compare(name_end, 2, " {") != 0) continue;  // a declaration, not a definition
    ++structs;
    ASSERT_TRUE(listed.count(name)) << name << " is not in contract.def";
    EXPECT_EQ(listed[name], members_declared(text, name)) << name;
  }
  EXPECT_EQ(structs, listed.size());
  // Every MH_ constant the headers define is listed, but for the ones that
  // are not a contract: the export attribute, the initializer of the version,
  // and its minor and patch (which later minors raise).
  const std::vector<std::string> not_contract = {"MH_PLUGIN_EXPORT", "MH_ABI_VERSION_INIT",
                                                 "MH_ABI_VERSION_MINOR", "MH_ABI_VERSION_PATCH"};
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::string name;
    if (line.rfind("#define MH_", 0) == 0) {
      name = line.substr(8, line.find_first_of(" \\(", 8) - 8);
    } else {
      const size_t at = line.find_first_not_of(' ');
      if (at == std::string::npos || line.compare(at, 3, "MH_") != 0) continue;
      const size_t end = line.find_first_of(" =,", at);
      if (end == std::string::npos || line.find('=', at) == std::string::npos) continue;
      name = line.substr(at, end - at);  // an enumerator: "MH_OK = 0,"
    }
    if (std::find(not_contract.begin(), not_contract.end(), name) != not_contract.end()) continue;
    EXPECT_NE(std::find(constants.begin(), constants.end(), name), constants.end())
        << name << " is not in contract.def";
  }
}

// Within each frozen struct the listed fields follow one another with no more
// than alignment padding between them and after the last: the list is the
// layout, not a selection of it.
TEST(FrozenAbi, TheListedFieldsTileEachFrozenStruct) {
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& s = mh_abi_frozen[i];
    if (s.kind != MH_ABI_RECORD_STRUCT) continue;
    size_t end = 0;
    size_t j = i + 1;
    for (; j < mh_abi_frozen_count && mh_abi_frozen[j].kind == MH_ABI_RECORD_FIELD; ++j) {
      const mh_abi_record& f = mh_abi_frozen[j];
      const size_t aligned = (end + f.align - 1) / f.align * f.align;
      EXPECT_EQ(f.offset, aligned) << label(f);
      end = f.offset + f.size;
    }
    EXPECT_GT(j, i + 1) << s.name << " lists no fields";
    EXPECT_EQ(s.size, (end + s.align - 1) / s.align * s.align) << s.name;
  }
}

TEST(FrozenAbi, EveryFieldOfThreeZeroKeepsItsOffsetSizeAndAlignment) {
  expect_same_entries();
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& was = mh_abi_frozen[i];
    const mh_abi_record& is = mh_abi_current[i];
    if (was.kind != MH_ABI_RECORD_FIELD) continue;
    EXPECT_EQ(is.offset, was.offset) << label(was) << " moved";
    EXPECT_EQ(is.size, was.size) << label(was) << " changed size";
    EXPECT_EQ(is.align, was.align) << label(was) << " changed alignment";
  }
}

TEST(FrozenAbi, StructsOnlyGrowAndKeepTheirAlignment) {
  expect_same_entries();
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& was = mh_abi_frozen[i];
    const mh_abi_record& is = mh_abi_current[i];
    if (was.kind != MH_ABI_RECORD_STRUCT) continue;
    EXPECT_GE(is.size, was.size) << was.name << " shrank";
    EXPECT_EQ(is.align, was.align) << was.name << " changed alignment";
  }
}

// What a later minor appends is announced by its number: a host reads a
// plugin's struct up to its struct_size, and the minor says which fields
// that can hold (types.h).
TEST(FrozenAbi, AStructThatGrewComesWithALaterMinorOfTheSameMajor) {
  expect_same_entries();
  EXPECT_EQ(mh_abi_current_major, mh_abi_frozen_major);
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& was = mh_abi_frozen[i];
    if (was.kind == MH_ABI_RECORD_STRUCT && mh_abi_current[i].size > was.size) {
      EXPECT_GT(mh_abi_current_minor, mh_abi_frozen_minor) << was.name << " grew";
    }
  }
}

TEST(FrozenAbi, EveryConstantOfThreeZeroKeepsItsValue) {
  expect_same_entries();
  for (size_t i = 0; i < mh_abi_frozen_count; ++i) {
    const mh_abi_record& was = mh_abi_frozen[i];
    const mh_abi_record& is = mh_abi_current[i];
    if (was.kind == MH_ABI_RECORD_INTEGER) {
      EXPECT_EQ(is.value, was.value) << was.name;
    } else if (was.kind == MH_ABI_RECORD_STRING) {
      EXPECT_STREQ(is.text, was.text) << was.name;
    }
  }
}
