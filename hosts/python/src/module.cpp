// The extension module monohydra._monohydra: the embedding API
// (monohydra/simulation.hpp) for Python, kept thin; the package's
// __init__.py gives it Python's manners (keyword arguments, Results with
// NumPy columns, picklable snapshots). Every call that steps releases the
// GIL, so one Simulation per thread runs in parallel. A failing call raises
// InputError (a model, a name or a value that is wrong: nothing changed) or
// SimulationError (a step that failed: the run keeps its last accepted
// state), both monohydra.Error, with the library's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "batch.hpp"
#include "errors.hpp"
#include "monohydra/simulation.hpp"

namespace py = pybind11;

namespace {

using monohydra::python::advance_in_chunks;
using monohydra::python::as_input;
using monohydra::python::as_run;
using monohydra::python::InputError;
using monohydra::python::kStepsBetweenSignals;
using monohydra::python::SimulationError;
using monohydra::python::step_in_chunks;
using monohydra::python::take_signals;

using Settings = monohydra::Simulation::Settings;

// A Kalman filter driving a run (monohydra::Estimator); the Python object
// keeps its run alive (keep_alive). An update that stops the filter (it
// diverges, a step fails) raises SimulationError; the package checks the
// arguments first.
class Filter {
 public:
  explicit Filter(monohydra::Estimator e) : est_(std::move(e)) {}

  void update(double t, const std::vector<double>& readings) {
    py::gil_scoped_release unlocked;
    as_run([&] {
      est_.update(t, readings);
      return 0;
    });
  }
  std::vector<std::string> states() const {
    return as_input([&] { return est_.states(); });
  }
  std::vector<std::string> units() const {
    return as_input([&] { return est_.state_units(); });
  }
  std::vector<std::string> sensors() const {
    return as_input([&] { return est_.sensors(); });
  }
  std::vector<double> state() const {
    return as_input([&] { return est_.state(); });
  }
  // n x n, row-major for NumPy (the covariance is symmetric: the same).
  py::array_t<double> covariance() const {
    const std::vector<double> p = as_input([&] { return est_.covariance(); });
    const auto n = static_cast<py::ssize_t>(std::lround(std::sqrt(static_cast<double>(p.size()))));
    py::array_t<double> out({n, n});
    std::copy(p.begin(), p.end(), out.mutable_data());
    return out;
  }
  std::vector<double> innovation() const {
    return as_input([&] { return est_.innovation(); });
  }
  std::vector<double> innovation_sd() const {
    return as_input([&] { return est_.innovation_sd(); });
  }
  double nis() const {
    return as_input([&] { return est_.nis(); });
  }

 private:
  monohydra::Estimator est_;
};

// A run, from Python: the C++ layer's object behind a unique_ptr (it moves).
class Run {
 public:
  explicit Run(monohydra::Simulation sim) : sim_(std::move(sim)) {}

  static Run open_file(const std::string& path, const Settings& settings) {
    return Run(as_input([&] { return monohydra::Simulation::open_file(path, settings); }));
  }
  static Run open_text(const std::string& text, const std::string& label,
                       const std::string& base_dir, const Settings& settings) {
    return Run(as_input(
        [&] { return monohydra::Simulation::open_text(text, label, base_dir, settings); }));
  }

  // The stepping calls release the GIL, look at Python's signals every
  // kStepsBetweenSignals steps (Ctrl-C: KeyboardInterrupt, the run at an
  // accepted state) and return what the plugins warned of ("" nothing).
  std::string start() {
    const py::gil_scoped_release unlocked;
    as_run([&] {
      sim_.start();
      return 0;
    });
    return sim_.take_warning();
  }
  std::string step(int64_t n) {
    if (n < 0) throw InputError(monohydra::Error(MHS_ERROR, "step: n must be >= 0"));
    const py::gil_scoped_release unlocked;
    std::string warned;
    step_in_chunks(static_cast<uint64_t>(n), [&](uint64_t k) {
      for (uint64_t i = 0; i < k; ++i) {
        as_run([&] {
          sim_.step();
          return 0;
        });
        gather(warned);
      }
    });
    return warned;
  }
  std::string advance(double t) {
    const py::gil_scoped_release unlocked;
    std::string warned;
    advance_in_chunks(time(), t, dt(), [&](double to) {
      as_run([&] {
        sim_.advance(to);
        return 0;
      });
      gather(warned);
    });
    return warned;
  }

  // The most values run() keeps (8 bytes each, and their text): a t_end
  // that would keep more is refused before the first step, not found out
  // by running out of memory.
  static constexpr double kMostKeptValues = 5e7;

  // Steps to t_end, keeping every row the command line would write from the
  // current state on: (values, texts, why it stopped early: "" when it did
  // not, warnings). A step that fails ends it with the rows before it.
  std::tuple<py::array_t<double>, std::vector<std::string>, std::string, std::string> rows_to(
      double t_end) {
    std::vector<double> values;
    std::vector<std::string> texts;
    std::string failed, warned;
    const size_t columns = as_input([&] { return sim_.row_names().size(); });
    const double steps = (t_end - time()) / dt();
    if (steps * static_cast<double>(columns) > kMostKeptValues)
      throw InputError(monohydra::Error(
          MHS_ERROR, "run(t_end=" + std::to_string(t_end) + "): up to " +
                         std::to_string(static_cast<long long>(steps)) + " rows of " +
                         std::to_string(columns) +
                         " columns is more than run() keeps (5e7 values); step with advance() "
                         "and read value(), or run to an earlier t_end"));
    {
      const py::gil_scoped_release unlocked;
      const double half = 0.5 * dt();
      const auto keep = [&] {
        if (!sim_.row_due()) return;
        const std::vector<double> row = sim_.row();
        values.insert(values.end(), row.begin(), row.end());
        texts.push_back(sim_.row_text(false));
      };
      try {
        sim_.advance(sim_.time());  // starts the run if it has not (no step taken)
        keep();
        for (uint64_t k = 1; sim_.time() < t_end - half; ++k) {
          sim_.step();
          gather(warned);
          keep();
          if (k % kStepsBetweenSignals == 0) take_signals();
        }
      } catch (const monohydra::Error& e) {
        failed = e.what();
      }
    }
    const auto rows = static_cast<py::ssize_t>(texts.size());
    py::array_t<double> out({rows, static_cast<py::ssize_t>(columns)});
    std::copy(values.begin(), values.end(), out.mutable_data());
    return {out, texts, failed, warned};
  }

  double time() const {
    return as_input([&] { return sim_.time(); });
  }
  int64_t steps() const {
    return as_input([&] { return sim_.steps(); });
  }
  double dt() const {
    return as_input([&] { return sim_.dt(); });
  }
  double t_end() const {
    return as_input([&] { return sim_.t_end(); });
  }

  // (kind, name, qualified, unit, min, max) of every variable.
  std::vector<py::tuple> variables() const {
    std::vector<py::tuple> out;
    for (const monohydra::Variable& v : as_input([&] { return sim_.variables(); }))
      out.push_back(
          py::make_tuple(static_cast<int>(v.kind), v.name, v.qualified, v.unit, v.min, v.max));
    return out;
  }
  uint32_t find(const std::string& name) const {
    return as_input([&] { return sim_.find(name); });
  }
  double get(uint32_t index) const {
    return as_input([&] { return sim_.get(index); });
  }
  // The value set (as clamped by the input's declaration) and a warning, if any.
  std::string set(uint32_t index, double value) {
    return as_input([&] {
      sim_.set(index, value);
      return sim_.take_warning();
    });
  }
  void set_parameter(const std::string& path, double value) {
    as_input([&] {
      sim_.set_parameter(path, value);
      return 0;
    });
  }
  std::string warning() { return sim_.take_warning(); }

  // (A, B, C, D as n x n ... NumPy arrays, t, states, state units, inputs,
  // input units, outputs, output units).
  py::tuple linearize(const std::vector<std::string>& outputs) {
    const monohydra::Linearization lin = as_input([&] { return sim_.linearize(outputs); });
    const auto matrix = [](const std::vector<double>& column_major, uint32_t rows, uint32_t cols) {
      py::array_t<double> out({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
      auto view = out.mutable_unchecked<2>();
      for (uint32_t j = 0; j < cols; ++j)
        for (uint32_t i = 0; i < rows; ++i)
          view(i, j) = column_major[static_cast<size_t>(j) * rows + i];
      return out;
    };
    return py::make_tuple(matrix(lin.A, lin.n, lin.n), matrix(lin.B, lin.n, lin.m),
                          matrix(lin.C, lin.p, lin.n), matrix(lin.D, lin.p, lin.m), lin.t,
                          lin.states, lin.state_units, lin.inputs, lin.input_units, lin.outputs,
                          lin.output_units);
  }
  void track_sensitivities(const std::vector<std::string>& paths) {
    as_input([&] {
      sim_.track_sensitivities(paths);
      return 0;
    });
  }
  std::vector<double> sensitivities(uint32_t index) const {
    return as_input([&] { return sim_.sensitivities(index); });
  }
  std::vector<std::string> row_names() const {
    return as_input([&] { return sim_.row_names(); });
  }
  std::string header() const {
    return as_input([&] { return sim_.row_text(true); });
  }

  Filter estimator(const std::string& filter, const std::vector<std::string>& params,
                   const std::vector<std::string>& noise_names, const std::vector<double>& plant,
                   const std::vector<double>& initial) {
    return as_input([&] {
      monohydra::EstimatorOptions o;
      o.filter = filter;
      o.params = params;
      for (size_t i = 0; i < noise_names.size(); ++i)
        o.noise.push_back({noise_names[i], plant.at(i), initial.at(i)});
      return Filter(sim_.estimator(o));
    });
  }

  py::bytes snapshot() {
    return as_input([&] {
      sim_.advance(sim_.time());  // a run not yet started starts: its initial state
      monohydra::Snapshot s = sim_.snapshot();
      const std::vector<unsigned char> bytes = sim_.bytes(s);
      return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    });
  }
  void restore(const py::bytes& data) {
    const std::string raw = data;  // a copy: the bytes object is Python's
    as_input([&] {
      const monohydra::Snapshot s =
          sim_.snapshot_from(std::vector<unsigned char>(raw.begin(), raw.end()));
      sim_.restore(s);
      return 0;
    });
  }

 private:
  // A warning of the call just made, added to those of the steps before.
  void gather(std::string& warned) {
    const std::string w = sim_.take_warning();
    if (w.empty() || warned.find(w) != std::string::npos) return;
    warned += (warned.empty() ? "" : "\n") + w;
  }

  monohydra::Simulation sim_;
};

}  // namespace

PYBIND11_MODULE(_monohydra, m) {
  m.doc() = "monohydra's engine: the embedding API (monohydra/simulation.h) for Python";
  static py::exception<monohydra::Error> error(m, "Error");
  static py::exception<InputError> input_error(m, "InputError", error.ptr());
  static py::exception<SimulationError> simulation_error(m, "SimulationError", error.ptr());
  // NOLINTNEXTLINE(performance-unnecessary-value-param): pybind11 takes a void(*)(exception_ptr)
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const SimulationError& e) {
      PyErr_SetString(simulation_error.ptr(), e.what());
    } catch (const monohydra::Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
  monohydra::python::bind_batch(m);
  m.attr("API_VERSION") = py::make_tuple(mhs_api_version() >> 16, mhs_api_version() & 0xffffu);
  m.attr("COORDINATE") = static_cast<int>(MHS_COORDINATE);
  m.attr("COORDINATE_RATE") = static_cast<int>(MHS_COORDINATE_RATE);
  m.attr("STATE") = static_cast<int>(MHS_STATE);
  m.attr("OUTPUT") = static_cast<int>(MHS_OUTPUT);
  m.attr("INPUT") = static_cast<int>(MHS_INPUT);

  py::class_<Run>(m, "_Run")
      .def_static("open_file", &Run::open_file, py::arg("path"), py::arg("settings"))
      .def_static("open_text", &Run::open_text, py::arg("text"), py::arg("label"),
                  py::arg("base_dir"), py::arg("settings"))
      .def("start", &Run::start)
      .def("step", &Run::step, py::arg("n") = 1)
      .def("advance", &Run::advance, py::arg("t"))
      .def("warning", &Run::warning)
      .def("linearize", &Run::linearize, py::arg("outputs"))
      .def("rows_to", &Run::rows_to, py::arg("t_end"))
      .def_property_readonly("time", &Run::time)
      .def_property_readonly("steps", &Run::steps)
      .def_property_readonly("dt", &Run::dt)
      .def_property_readonly("t_end", &Run::t_end)
      .def("variables", &Run::variables)
      .def("find", &Run::find, py::arg("name"))
      .def("get", &Run::get, py::arg("index"))
      .def("set", &Run::set, py::arg("index"), py::arg("value"))
      .def("set_parameter", &Run::set_parameter, py::arg("path"), py::arg("value"))
      .def("track_sensitivities", &Run::track_sensitivities, py::arg("paths"))
      .def("sensitivities", &Run::sensitivities, py::arg("index"))
      .def("row_names", &Run::row_names)
      .def("header", &Run::header)
      .def("estimator", &Run::estimator, py::keep_alive<0, 1>(), py::arg("filter"),
           py::arg("params"), py::arg("noise_names"), py::arg("plant"), py::arg("initial"))
      .def("snapshot", &Run::snapshot)
      .def("restore", &Run::restore, py::arg("data"));

  py::class_<Filter>(m, "_Filter")
      .def("update", &Filter::update, py::arg("t"), py::arg("readings"))
      .def("states", &Filter::states)
      .def("units", &Filter::units)
      .def("sensors", &Filter::sensors)
      .def("state", &Filter::state)
      .def("covariance", &Filter::covariance)
      .def("innovation", &Filter::innovation)
      .def("innovation_sd", &Filter::innovation_sd)
      .def("nis", &Filter::nis);
}
