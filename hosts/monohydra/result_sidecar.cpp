#include "result_sidecar.hpp"

#include <nettle/sha2.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli_support.hpp"
#include "monohydra/core/linear_solver.hpp"
#include "monohydra/types.h"

namespace mh::cli {
namespace {

// A JSON string literal (RFC 8259: quote, backslash and control characters escaped).
std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// Round-trip precision: the sidecar must reproduce the run.
std::string json_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

std::string sidecar_path(const std::string& result) {
  return std::filesystem::path(result).replace_extension(".meta.json").string();
}

std::string file_sha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  sha256_ctx ctx;
  sha256_init(&ctx);
  std::array<char, 65536> block{};
  while (in) {
    in.read(block.data(), block.size());
    const std::streamsize n = in.gcount();
    if (n > 0)
      sha256_update(&ctx, static_cast<size_t>(n), reinterpret_cast<const uint8_t*>(block.data()));
  }
  if (in.bad()) return "";
  std::array<uint8_t, SHA256_DIGEST_SIZE> digest{};
  sha256_digest(&ctx, digest.size(), digest.data());
  std::string hex;
  char buf[3];
  for (const uint8_t b : digest) {
    std::snprintf(buf, sizeof buf, "%02x", b);
    hex += buf;
  }
  return hex;
}

bool write_sidecar(const std::string& result, const ResultProvenance& p) {
  std::error_code ec;
  const std::string model_abs = std::filesystem::absolute(p.model_path, ec).string();
  std::ostringstream j;
  j << "{\n"
    << "  \"result\": " << json_string(std::filesystem::path(result).filename().string()) << ",\n"
    << "  \"monohydra_version\": " << json_string(MONOHYDRA_VERSION) << ",\n"
    << "  \"abi_version\": "
    << json_string(std::to_string(MH_ABI_VERSION_MAJOR) + "." +
                   std::to_string(MH_ABI_VERSION_MINOR) + "." +
                   std::to_string(MH_ABI_VERSION_PATCH))
    << ",\n"
    << "  \"command_line\": " << json_string(command_line()) << ",\n"
    << "  \"working_directory\": " << json_string(std::filesystem::current_path(ec).string())
    << ",\n"
    << "  \"model\": {\"path\": " << json_string(ec ? p.model_path : model_abs)
    << ", \"sha256\": " << json_string(file_sha256(p.model_path)) << "},\n"
    << "  \"settings\": {\n"
    << "    \"formulation\": " << json_string(p.formulation) << ",\n"
    << "    \"integrator\": " << json_string(p.integrator) << ",\n"
    << "    \"dt\": " << json_number(p.solver.dt) << ",\n"
    << "    \"t_end\": " << json_number(p.solver.t_end) << ",\n"
    << "    \"max_iterations\": " << p.solver.max_iterations << ",\n"
    << "    \"max_step_halvings\": " << p.solver.max_step_halvings << ",\n"
    << "    \"tol_position\": " << json_number(p.solver.tol_position) << ",\n"
    << "    \"linear\": " << json_string(to_string(p.solver.linear)) << ",\n"
    << "    \"newton\": " << json_string(to_string(p.solver.newton)) << ",\n"
    << "    \"line_search\": " << (p.solver.line_search ? "true" : "false") << ",\n"
    << "    \"output_interval\": "
    << (p.output_interval ? json_number(*p.output_interval) : std::string("null")) << ",\n"
    << "    \"real_time_newton_cap\": "
    << (p.real_time_cap > 0 ? std::to_string(p.real_time_cap) : std::string("null")) << ",\n"
    << "    \"explicit_stability\": " << json_string(to_string(p.solver.explicit_stability))
    << ",\n"
    << "    \"set\": [";
  for (size_t i = 0; i < p.set.size(); ++i)
    j << (i == 0 ? "" : ", ") << "{\"path\": " << json_string(p.set[i].path)
      << ", \"value\": " << json_string(p.set[i].value) << "}";
  j << "],\n"
    << "    \"sensor_seed\": "
    << (p.sensor_seed ? std::to_string(*p.sensor_seed) : std::string("null")) << "\n"
    << "  },\n"
    << "  \"explicit_stability\": ";
  if (p.stability != nullptr && p.stability->checks > 0) {
    const ExplicitStability& s = *p.stability;
    j << "{\"unstable\": " << (s.unstable ? "true" : "false") << ", \"checks\": " << s.checks
      << ", \"t\": " << json_number(s.t) << ", \"step\": " << s.step
      << ", \"dt\": " << json_number(s.h) << ", \"amplification\": " << json_number(s.amplification)
      << ", \"eigenvalue\": [" << json_number(s.eigenvalue.real()) << ", "
      << json_number(s.eigenvalue.imag()) << "], \"stable_dt\": "
      << (std::isinf(s.stable_dt) ? std::string("null") : json_number(s.stable_dt)) << "},\n";
  } else {
    j << "null,\n";
  }
  j << "  \"plugins\": [";
  for (size_t i = 0; i < p.plugins.size(); ++i) {
    const host::UsedComponent& u = p.plugins[i];
    j << (i == 0 ? "\n" : ",\n") << "    {\"kind\": " << json_string(to_string(u.kind))
      << ", \"id\": " << json_string(u.id) << ", \"version\": " << json_string(u.version)
      << ", \"library\": " << json_string(u.library)
      << ", \"library_sha256\": " << json_string(file_sha256(u.library)) << "}";
  }
  j << (p.plugins.empty() ? "]\n" : "\n  ]\n") << "}\n";
  const std::string path = sidecar_path(result);
  std::ofstream out(path);
  out << j.str();
  out.close();
  if (!out) {
    std::cerr << "monohydra: cannot write '" << path << "'\n";
    return false;
  }
  return true;
}

}  // namespace mh::cli
