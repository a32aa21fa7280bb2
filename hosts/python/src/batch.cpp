#include "batch.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "errors.hpp"
#include "monohydra/simulation.hpp"

namespace py = pybind11;

namespace monohydra::python {

namespace {

class BatchRuns {
 public:
  explicit BatchRuns(monohydra::Batch b) : batch_(std::move(b)) {}

  static BatchRuns open_file(const std::string& path, uint32_t runs, uint32_t threads,
                             const Simulation::Settings& settings) {
    return BatchRuns(as_input([&] { return Batch::open_file(path, runs, threads, settings); }));
  }
  static BatchRuns open_text(const std::string& text, const std::string& label,
                             const std::string& base_dir, uint32_t runs, uint32_t threads,
                             const Simulation::Settings& settings) {
    return BatchRuns(
        as_input([&] { return Batch::open_text(text, label, base_dir, runs, threads, settings); }));
  }

  uint32_t runs() const {
    return as_input([&] { return batch_.size(); });
  }
  uint32_t threads() const {
    return as_input([&] { return batch_.threads(); });
  }
  double dt() const {
    return as_input([&] { return batch_.dt(); });
  }
  double t_end() const {
    return as_input([&] { return batch_.t_end(); });
  }
  // The warning of opening ("" none).
  std::string warning() const { return batch_.warning(); }

  std::vector<py::tuple> variables() const {
    std::vector<py::tuple> out;
    for (const monohydra::Variable& v : as_input([&] { return batch_.variables(); }))
      out.push_back(
          py::make_tuple(static_cast<int>(v.kind), v.name, v.qualified, v.unit, v.min, v.max));
    return out;
  }
  uint32_t find(const std::string& name) const {
    return as_input([&] { return batch_.find(name); });
  }
  void set_parameter(uint32_t run, const std::string& path, double value) {
    as_input([&] {
      batch_.set_parameter(run, path, value);
      return 0;
    });
  }

  // Each returns the message that names the runs stopped ("" when none is).
  std::string start() {
    const py::gil_scoped_release unlocked;
    return stepped(as_input([&] { return batch_.start(); }));
  }
  std::string step(int64_t n) {
    if (n < 0) throw InputError(Error(MHS_ERROR, "step: n must be >= 0"));
    const py::gil_scoped_release unlocked;
    size_t stopped = 0;
    step_in_chunks(static_cast<uint64_t>(n),
                   [&](uint64_t k) { stopped = as_input([&] { return batch_.step(k); }); });
    return stepped(stopped);
  }
  std::string advance(double t) {
    const py::gil_scoped_release unlocked;
    size_t stopped = 0;
    advance_in_chunks(latest(), t, dt(),
                      [&](double to) { stopped = as_input([&] { return batch_.advance(to); }); });
    return stepped(stopped);
  }

  py::array_t<double> get(uint32_t index) const {
    const std::vector<double> v = as_input([&] { return batch_.get(index); });
    py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  }
  // The message naming the runs whose value was clamped ("" none).
  std::string set(uint32_t index, const std::vector<double>& values) {
    return as_input([&] {
      batch_.set(index, values);
      return batch_.warning();
    });
  }
  // (stopped, time, steps, reason) of every run.
  std::vector<py::tuple> status() const {
    std::vector<py::tuple> out;
    const uint32_t n = runs();
    for (uint32_t k = 0; k < n; ++k) {
      const Batch::RunStatus s = as_input([&] { return batch_.status(k); });
      out.push_back(py::make_tuple(s.stopped, s.time, s.steps, s.reason));
    }
    return out;
  }
  // Every run's state as bytes (mhs_batch_snapshot_bytes), and back.
  py::bytes snapshot() {
    return as_input([&] {
      const std::vector<unsigned char> bytes = batch_.bytes(batch_.snapshot());
      return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    });
  }
  // The message naming runs whose model values differ from the snapshot's ("" none).
  std::string restore(const py::bytes& data) {
    const std::string raw = data;  // a copy: the bytes object is Python's
    return as_input([&] {
      const Batch::Snapshot s =
          batch_.snapshot_from(std::vector<unsigned char>(raw.begin(), raw.end()));
      batch_.restore(s);
      return batch_.warning();
    });
  }

 private:
  // The latest time of any run, stopped or not: an advance to a time before
  // it is refused, so the chunks start there.
  double latest() const {
    double t = 0.0;
    const uint32_t n = batch_.size();
    for (uint32_t k = 0; k < n; ++k) t = std::max(t, batch_.status(k).time);
    return t;
  }
  std::string stepped(size_t stopped) const { return stopped == 0 ? "" : batch_.warning(); }

  Batch batch_;
};

}  // namespace

void bind_batch(py::module_& m) {
  // Opaque to Python: monohydra.BatchSnapshot holds it.
  const py::class_<Batch::Snapshot, std::shared_ptr<Batch::Snapshot>> snapshot(m, "_BatchSnapshot");
  py::class_<BatchRuns>(m, "_Batch")
      .def_static("open_file", &BatchRuns::open_file, py::arg("path"), py::arg("runs"),
                  py::arg("threads"), py::arg("settings"))
      .def_static("open_text", &BatchRuns::open_text, py::arg("text"), py::arg("label"),
                  py::arg("base_dir"), py::arg("runs"), py::arg("threads"), py::arg("settings"))
      .def_property_readonly("runs", &BatchRuns::runs)
      .def_property_readonly("threads", &BatchRuns::threads)
      .def_property_readonly("dt", &BatchRuns::dt)
      .def_property_readonly("t_end", &BatchRuns::t_end)
      .def_property_readonly("warning", &BatchRuns::warning)
      .def("variables", &BatchRuns::variables)
      .def("find", &BatchRuns::find, py::arg("name"))
      .def("set_parameter", &BatchRuns::set_parameter, py::arg("run"), py::arg("path"),
           py::arg("value"))
      .def("start", &BatchRuns::start)
      .def("step", &BatchRuns::step, py::arg("n") = 1)
      .def("advance", &BatchRuns::advance, py::arg("t"))
      .def("get", &BatchRuns::get, py::arg("index"))
      .def("set", &BatchRuns::set, py::arg("index"), py::arg("values"))
      .def("status", &BatchRuns::status)
      .def("snapshot", &BatchRuns::snapshot)
      .def("restore", &BatchRuns::restore, py::arg("data"));
}

}  // namespace monohydra::python
