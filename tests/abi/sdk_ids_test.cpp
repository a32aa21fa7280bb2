// The ids of the SDK's services and extensions, as docs/sdk.md lists them:
// a host and a plugin meet on these exact strings, so the guide's table is
// held to the headers (every id defined there, with its string, revision,
// kind, header and the minor that added it; an id of the frozen 3.0 headers
// says 3.0, any other a later minor of this major, none past the SDK's own).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include "build_paths.hpp"
#include "text_file.hpp"

namespace {

using mh::test::read_text;

namespace fs = std::filesystem;

struct Defined {
  std::string text;    // "monohydra.options/3"
  std::string header;  // "host.h"
};

// MH_SERVICE_* and MH_EXT_* of every header in `folder`.
std::map<std::string, Defined> ids_in(const fs::path& folder) {
  std::map<std::string, Defined> out;
  const std::regex define(R"re(#define\s+(MH_(?:SERVICE|EXT)_\w+)\s+"([^"]+)")re");
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".h") continue;
    const std::string text = read_text(entry.path());
    for (std::sregex_iterator m(text.begin(), text.end(), define), end; m != end; ++m)
      out[(*m)[1]] = {(*m)[2], entry.path().filename().string()};
  }
  return out;
}

int defined_number(const std::string& header_text, const std::string& name) {
  std::smatch m;
  const std::regex re("#define\\s+" + name + "\\s+(\\d+)u");
  return std::regex_search(header_text, m, re) ? std::stoi(m[1]) : -1;
}

struct Row {
  std::string text, revision, kind, header, since;
};

TEST(SdkIds, TheSdkGuideListsEveryIdOfTheHeadersWithItsRevision) {
  const fs::path source = mh::test::paths::source_dir;
  const std::map<std::string, Defined> headers = ids_in(source / "sdk/include/monohydra");
  const std::map<std::string, Defined> frozen = ids_in(source / "tests/abi/sdk-3.0/monohydra");
  ASSERT_GE(headers.size(), 17u);  // as many as 3.2 defines, at least
  ASSERT_EQ(frozen.size(), 7u);    // as 3.0 shipped them
  const std::string types = read_text(source / "sdk/include/monohydra/types.h");
  const int major = defined_number(types, "MH_ABI_VERSION_MAJOR");
  const int minor = defined_number(types, "MH_ABI_VERSION_MINOR");
  ASSERT_GE(major, 3);
  ASSERT_GE(minor, 0);

  const std::string guide = read_text(source / "docs/sdk.md");
  const std::string title = "### Every id, its revision and the minor that added it";
  const size_t at = guide.find(title);
  ASSERT_NE(at, std::string::npos) << "docs/sdk.md has no section '" << title << "'";
  const std::string section = guide.substr(at, guide.find("\n#", at + title.size()) - at);
  const std::regex row(
      R"re(\n\| `(MH_\w+)` \| `"([^"]+)"` \| (\d+) \| (\w+) \| `([\w.]+)` \| ([^|\n]+) \|)re");
  std::map<std::string, Row> table;
  for (std::sregex_iterator m(section.begin(), section.end(), row), end; m != end; ++m)
    table[(*m)[1]] = {(*m)[2], (*m)[3], (*m)[4], (*m)[5], (*m)[6]};

  for (const auto& [id, def] : headers) {
    const auto it = table.find(id);
    if (it == table.end()) {
      ADD_FAILURE() << id << " (" << def.text << ", " << def.header
                    << ") is not in docs/sdk.md's table of ids";
      continue;
    }
    const Row& r = it->second;
    EXPECT_EQ(r.text, def.text) << id;
    EXPECT_EQ(r.header, def.header) << id;
    EXPECT_EQ(r.revision, def.text.substr(def.text.rfind('/') + 1)) << id;
    EXPECT_EQ(r.kind, id.rfind("MH_SERVICE_", 0) == 0 ? "service" : "extension") << id;
    std::smatch v;
    ASSERT_TRUE(std::regex_search(r.since, v, std::regex(R"(^(\d+)\.(\d+))")))
        << id << ": " << r.since;
    const int since_major = std::stoi(v[1]), since_minor = std::stoi(v[2]);
    EXPECT_EQ(since_major, major) << id << ": " << r.since;
    EXPECT_LE(since_minor, minor) << id << " says " << r.since << ", the SDK is " << major << "."
                                  << minor;
    if (frozen.count(id) != 0)
      EXPECT_EQ(since_minor, 0) << id << " is in the frozen 3.0 headers: " << r.since;
    else
      EXPECT_GT(since_minor, 0) << id << " is not in the frozen 3.0 headers: " << r.since;
  }
  for (const auto& [id, r] : table)
    EXPECT_EQ(headers.count(id), 1u)
        << id << " (" << r.text << ") is in docs/sdk.md's table but no header defines it";
}

}  // namespace
