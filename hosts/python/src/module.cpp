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
#include <utility>
#include <vector>

#include "batch.hpp"
#include "errors.hpp"
#include "monohydra/simulation.hpp"

namespace py = pybind11;

namespace {

using monohydra::python::as_input;
using monohydra::python::as_run;
using monohydra::python::InputError;
using monohydra::python::SimulationError;

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

  void start() {
    py::gil_scoped_release unlocked;
    as_run([&] {
      sim_.start();
      return 0;
    });
  }
  void step(int64_t n) {
    if (n < 0) throw InputError(monohydra::Error(MHS_ERROR, "step: n must be >= 0"));
    py::gil_scoped_release unlocked;
    as_run([&] {
      for (int64_t k = 0; k < n; ++k) sim_.step();
      return 0;
    });
  }
  void advance(double t) {
    py::gil_scoped_release unlocked;
    as_run([&] {
      sim_.advance(t);
      return 0;
    });
  }

  // Steps to t_end, keeping every row the command line would write from the
  // current state on (its values and its CSV text): (values, texts).
  std::pair<py::array_t<double>, std::vector<std::string>> rows_to(double t_end) {
    std::vector<double> values;
    std::vector<std::string> texts;
    size_t columns = 0;
    {
      py::gil_scoped_release unlocked;
      as_run([&] {
        const double half = 0.5 * sim_.dt();
        const auto keep = [&] {
          if (!sim_.row_due()) return;
          const std::vector<double> row = sim_.row();
          columns = row.size();
          values.insert(values.end(), row.begin(), row.end());
          texts.push_back(sim_.row_text(false));
        };
        sim_.advance(sim_.time());  // starts the run if it has not (no step taken)
        keep();
        while (sim_.time() < t_end - half) {
          sim_.step();
          keep();
        }
        return 0;
      });
    }
    if (columns == 0) columns = sim_.row_names().size();
    const auto rows = static_cast<py::ssize_t>(texts.size());
    py::array_t<double> out({rows, static_cast<py::ssize_t>(columns)});
    std::copy(values.begin(), values.end(), out.mutable_data());
    return {out, texts};
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
      return sim_.warning();
    });
  }
  void set_parameter(const std::string& path, double value) {
    as_input([&] {
      sim_.set_parameter(path, value);
      return 0;
    });
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
