#include "checkpoint.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "monohydra/core/run_state_bytes.hpp"

namespace mh::cli {

void save_checkpoint(const Simulation& sim, const std::string& path) {
  std::vector<unsigned char> bytes;
  write_run_state_bytes(sim.save_state(), bytes);
  const std::string temporary = path + ".part";
  const auto fail = [&](const std::string& why) {
    std::remove(temporary.c_str());
    throw SimulationError(sim.time(), sim.step_index(),
                          "cannot write the state to '" + path + "': " + why);
  };
  {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (out)
      out.write(reinterpret_cast<const char*>(bytes.data()),
                static_cast<std::streamsize>(bytes.size()));
    if (out) out.flush();
    if (!out) fail(errno != 0 ? std::strerror(errno) : "write failed");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) fail(std::strerror(errno));
}

void load_checkpoint(const std::string& path, RunState& into) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunStateError("'" + path + "' cannot be read: " + std::strerror(errno));
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  try {
    read_run_state_bytes(bytes.data(), bytes.size(), into);
  } catch (const RunStateError& err) {
    throw RunStateError("'" + path + "': " + err.what());
  }
}

}  // namespace mh::cli
