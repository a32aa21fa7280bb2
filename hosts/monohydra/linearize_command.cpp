// monohydra linearize MODEL --at T: runs the model to T through the same
// engine as `run` and writes the state-space matrices A, B, C, D about that
// state (linearization.hpp) with the names of their rows and columns, and
// the eigenvalues of A, as one YAML document (docs/cli.md): yaml.safe_load
// and numpy.array(doc["A"]) read it.
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "commands.hpp"
#include "monohydra/core/linearization.hpp"
#include "run_setup.hpp"
#include "subcommand_parser.hpp"

namespace mh::cli {

namespace {

// Every double to the bit (17 significant digits).
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", v);
  return text;
}

// A YAML string: quoted when it is not a plain word.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

void write_variables(std::ostream& out, const char* key, const std::vector<LinearVariable>& vars) {
  out << key << ":";
  if (vars.empty()) out << " []";
  out << '\n';
  for (const LinearVariable& v : vars)
    out << "  - {name: " << quoted(v.name) << ", unit: " << quoted(v.unit) << "}\n";
}

// A matrix as a list of its rows (empty rows when it has no columns).
void write_matrix(std::ostream& out, const char* key, const Eigen::MatrixXd& m) {
  out << key << ":";
  if (m.rows() == 0) out << " []";
  out << '\n';
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    out << "  - [";
    for (Eigen::Index j = 0; j < m.cols(); ++j) out << (j > 0 ? ", " : "") << number(m(i, j));
    out << "]\n";
  }
}

}  // namespace

int linearize(const std::vector<std::string>& args) {
  const auto app_holder = subcommand_app(
      "linearize",
      "Run MODEL.yaml to --at T (default 0: the initial state) and write the state-space "
      "matrices A, B, C, D about that state over the model's inputs and the --outputs, with "
      "the eigenvalues of A, as YAML (stdout, or --out FILE).");
  CLI::App& app = *app_holder;
  std::vector<std::string> models;
  std::string at_text, outputs_text, out_path;
  RunRequest request;
  app.add_option("MODEL.yaml", models, "the model file");
  app.add_option("--at", at_text, "the time (s) to linearise at (default 0)");
  app.add_option("--outputs", outputs_text,
                 "the outputs Y, comma-separated: z1, z1_dot, states, outputs by name");
  app.add_option("--formulation", request.formulation, "replaces the model file's formulation");
  app.add_option("--integrator", request.integrator, "replaces the model file's integrator");
  app.add_option("--out", out_path, "write the YAML to FILE instead of stdout");
  if (const auto code = parse_subcommand(app, args)) return *code;
  if (models.size() != 1) {
    std::cerr << "monohydra: linearize needs one model file\n";
    return 2;
  }
  double at = 0.0;
  if (!at_text.empty()) {
    const std::optional<double> value = parse_number("--at", at_text);
    if (!value) return 2;
    if (!std::isfinite(*value) || *value < 0.0) {
      std::cerr << "monohydra: --at expects a time in s (0 or more), got '" << at_text << "'\n";
      return 2;
    }
    at = *value;
  }
  request.model_path = models.front();
  if (at > 0.0) request.overrides.t_end = at;  // the run's own checks of T against its dt
  const auto prepared = prepare_run(request);
  if (!prepared) return 2;
  Simulation& sim = *prepared->sim;
  const std::vector<std::string> outputs = split_list(outputs_text);
  // An unknown output is a usage error, found before the run to T.
  for (const std::string& name : outputs) {
    bool known = sim.state_index(name) >= 0 || sim.output_index(name) >= 0;
    for (const std::string& c : sim.coordinate_names())
      known = known || name == c || name == c + "_dot";
    if (!known) {
      try {
        sim.start();
        (void)mh::linearize(sim, {name});  // its message lists the names there are
      } catch (const std::invalid_argument& err) {
        std::cerr << "monohydra: --outputs: " << err.what() << '\n';
      } catch (const std::exception& err) {
        std::cerr << "monohydra: --outputs: unknown output '" << name << "' (" << err.what()
                  << ")\n";
      }
      return 2;
    }
  }
  Linearization lin;
  try {
    sim.start();
    const double dt = sim.settings().dt;
    while (sim.time() < at - 1e-6 * dt) sim.step();
    lin = mh::linearize(sim, outputs);
  } catch (const std::invalid_argument& err) {
    std::cerr << "monohydra: --outputs: " << err.what() << '\n';
    return 2;
  } catch (const std::exception& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 1;
  }

  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) {
      std::cerr << "monohydra: cannot write '" << out_path << "'\n";
      return 2;
    }
  }
  std::ostream& out = out_path.empty() ? std::cout : file;
  out << "# monohydra linearize: dX/dt = A X + B u, Y = C X + D u about the state at t;\n"
         "# matrices as lists of rows, in SI units of the names' units. Eigenvalues near\n"
         "# -2/h belong to directions the formulation projects out: ignore them.\n";
  out << "model: " << quoted(request.model_path) << '\n'
      << "formulation: " << quoted(sim.formulation_name()) << '\n'
      << "integrator: " << quoted(sim.integrator_name()) << '\n'
      << "t: " << number(lin.t) << '\n'
      << "h: " << number(lin.h) << '\n';
  write_variables(out, "states", lin.states);
  write_variables(out, "inputs", lin.inputs);
  write_variables(out, "outputs", lin.outputs);
  write_matrix(out, "A", lin.A);
  write_matrix(out, "B", lin.B);
  write_matrix(out, "C", lin.C);
  write_matrix(out, "D", lin.D);
  // The time constant -1/Re of a stable real eigenvalue (null otherwise).
  const std::vector<std::complex<double>> ev = eigenvalues(lin.A);
  out << "eigenvalues:" << (ev.empty() ? " []" : "") << '\n';
  for (const std::complex<double>& v : ev) {
    const bool real = v.imag() == 0.0;
    out << "  - {re: " << number(v.real()) << ", im: " << number(v.imag()) << ", time_constant: "
        << (real && v.real() < 0.0 ? number(-1.0 / v.real()) : std::string("null")) << "}\n";
  }
  if (!out) {
    std::cerr << "monohydra: cannot write '" << (out_path.empty() ? "stdout" : out_path) << "'\n";
    return 1;
  }
  return 0;
}

}  // namespace mh::cli
