#include "shipped_models.hpp"

#include <boost/dll/runtime_symbol_info.hpp>
#include <filesystem>

#include "build_tree.hpp"

namespace fs = std::filesystem;

namespace mh::cli {

std::string shipped_model(const std::string& name) {
  std::error_code ec;
  const fs::path exe_dir = boost::dll::program_location(ec).parent_path();
  for (const fs::path& dir :
       {exe_dir / ".." / "share" / "monohydra" / "models", fs::path(MONOHYDRA_INSTALL_MODELS),
        fs::path(build_tree::source_models)}) {
    const fs::path p = dir / name;
    if (fs::exists(p, ec)) return p.lexically_normal().string();
  }
  return "models/" + name;
}

}  // namespace mh::cli
