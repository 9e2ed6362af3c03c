// The `thermnet._thermnet` extension: Model, Result and the reports as Python objects. Every solve
// runs with the GIL released; JSON reports become dicts through the json module, so they carry
// exactly what the CLI writes.

#include "app/model_loading.hpp"
#include "kernel/core/solver_types.hpp"
#include "lang/units.hpp"
#include "python/model_session.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

namespace py = pybind11;
using thermnet::python::CalibrateRequest;
using thermnet::python::LoadError;
using thermnet::python::ModelSession;
using thermnet::python::SimulateRequest;

namespace {

/// A simulation result with numpy views: times (s) and temperatures (degC, one row per time).
struct PyResult {
  std::vector<std::string> nodes;
  py::array_t<double> times;
  py::array_t<double> temperatures;
  std::string integrator;
};

PyResult to_py(const thermnet::SimulationResult& r) {
  PyResult out;
  out.nodes = r.names;
  out.integrator = r.stats.integrator;
  out.times = py::array_t<double>(static_cast<py::ssize_t>(r.times.size()));
  std::copy(r.times.begin(), r.times.end(), out.times.mutable_data());
  const auto nt = static_cast<py::ssize_t>(r.times.size());
  const auto nn = static_cast<py::ssize_t>(r.names.size());
  out.temperatures = py::array_t<double>({nt, nn});
  auto t = out.temperatures.mutable_unchecked<2>();
  for (py::ssize_t k = 0; k < nt; ++k)
    for (py::ssize_t i = 0; i < nn; ++i)
      t(k, i) = r.temps[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] -
                thermnet::lang::kZeroCelsius;
  return out;
}

py::object json_to_python(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

SimulateRequest simulate_request(const std::string& case_name,
                                 const std::map<std::string, double>& params,
                                 const std::vector<std::string>& nodes,
                                 std::optional<double> duration, std::optional<double> output,
                                 double rtol, double atol, bool steady, bool sensors) {
  SimulateRequest q;
  q.case_name = case_name;
  for (const auto& [k, v] : params)
    q.params[k] = v;
  q.nodes = nodes;
  q.duration = duration;
  q.output = output;
  q.rtol = rtol;
  q.atol = atol;
  q.steady = steady;
  q.sensors = sensors;
  return q;
}

} // namespace

PYBIND11_MODULE(_thermnet, m) {
  m.doc() = "thermnet: lumped-parameter thermal networks (simulate, calibrate, diagnose)";
  m.attr("__version__") = THERMNET_VERSION;

  static py::exception<LoadError> model_error(m, "ModelError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const LoadError& e) {
      py::object type = py::reinterpret_borrow<py::object>(model_error.ptr());
      py::object err = type(e.what());
      err.attr("file") = e.file;
      err.attr("line") = e.line;
      err.attr("column") = e.column;
      PyErr_SetObject(model_error.ptr(), err.ptr());
    } catch (const thermnet::SolverError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  m.def(
      "load_plugin",
      [](const std::string& path) {
        if (auto err = thermnet::app::load_plugin(path))
          throw std::runtime_error(fmt::format("cannot load plugin '{}': {}", path, *err));
      },
      py::arg("path"),
      "Loads element/optimizer/estimator/hypothesis kinds from a plugin library (like --plugin).");

  py::class_<PyResult>(m, "Result", "Temperatures of a simulation: times [s], temperatures [degC]")
      .def_readonly("nodes", &PyResult::nodes,
                    "node names (then sensor names with sensors=True), one per column of "
                    "temperatures")
      .def_readonly("times", &PyResult::times, "output times, s (1-D numpy array)")
      .def_readonly("temperatures", &PyResult::temperatures,
                    "temperatures, degC: a (len(times), len(nodes)) numpy array")
      .def_readonly("integrator", &PyResult::integrator, "the integrator that ran (or steady)")
      .def(
          "to_pandas",
          [](const PyResult& r) {
            py::module_ pd = py::module_::import("pandas");
            py::object index = pd.attr("Index")(r.times, py::arg("name") = "time");
            return pd.attr("DataFrame")(r.temperatures, py::arg("index") = index,
                                        py::arg("columns") = r.nodes);
          },
          "A pandas DataFrame: index time [s], one column per node [degC] (needs pandas)")
      .def("__repr__", [](const PyResult& r) {
        return fmt::format("<thermnet.Result {} times x {} nodes>", r.times.size(), r.nodes.size());
      });

  py::class_<ModelSession, std::shared_ptr<ModelSession>>(m, "Model", "A checked thermnet model")
      .def_static(
          "load",
          [](const std::string& path) {
            return std::const_pointer_cast<ModelSession>(ModelSession::load(path));
          },
          py::arg("path"), "Loads and lints a .tnet file; errors raise ModelError(file:line:col).")
      .def_static(
          "from_string",
          [](const std::string& text, const std::string& name) {
            return std::const_pointer_cast<ModelSession>(ModelSession::from_text(text, name));
          },
          py::arg("text"), py::arg("name") = "<string>.tnet",
          "Loads a model from text; `name` is the path it is known by (includes and data files "
          "are read relative to it).")
      .def_property_readonly("name", [](const ModelSession& s) { return s.model().name(); })
      .def_property_readonly("path", [](const ModelSession& s) { return s.model().path(); })
      .def_property_readonly("nodes", &ModelSession::node_names,
                             "node and boundary names, declaration order")
      .def_property_readonly("cases", &ModelSession::case_names, "case names, declaration order")
      .def_property_readonly(
          "params",
          [](const ModelSession& s) {
            py::dict out;
            for (const auto& p : s.model().params()) {
              py::dict d;
              d["value"] = p.value;
              d["lo"] = p.lo ? py::cast(*p.lo) : py::none();
              d["hi"] = p.hi ? py::cast(*p.hi) : py::none();
              d["doc"] = p.doc;
              out[py::str(p.name)] = d;
            }
            return out;
          },
          "{name: {value, lo, hi, doc}} in SI units, declaration order")
      .def(
          "simulate",
          [](const ModelSession& s, const std::string& case_name,
             const std::map<std::string, double>& params, const std::vector<std::string>& nodes,
             std::optional<double> duration, std::optional<double> output, double rtol, double atol,
             bool sensors) {
            SimulateRequest q = simulate_request(case_name, params, nodes, duration, output, rtol,
                                                 atol, false, sensors);
            thermnet::SimulationResult r;
            {
              py::gil_scoped_release release;
              r = s.simulate(q);
            }
            return to_py(r);
          },
          py::arg("case") = "", py::arg("params") = std::map<std::string, double>{},
          py::arg("nodes") = std::vector<std::string>{}, py::arg("duration") = py::none(),
          py::arg("output") = py::none(), py::arg("rtol") = 1e-6, py::arg("atol") = 1e-6,
          py::arg("sensors") = false,
          "Simulates a case (params in SI, duration/output in s); returns a Result. With "
          "sensors=True each sensor's reading follows the nodes as a column named after it.")
      .def(
          "steady",
          [](const ModelSession& s, const std::string& case_name,
             const std::map<std::string, double>& params, const std::vector<std::string>& nodes) {
            SimulateRequest q = simulate_request(case_name, params, nodes, std::nullopt,
                                                 std::nullopt, 1e-6, 1e-6, true, false);
            thermnet::SimulationResult r;
            {
              py::gil_scoped_release release;
              r = s.simulate(q);
            }
            return to_py(r);
          },
          py::arg("case") = "", py::arg("params") = std::map<std::string, double>{},
          py::arg("nodes") = std::vector<std::string>{},
          "The steady state with the inputs at t = 0: a Result with one row at time 0.")
      .def(
          "calibrate",
          [](const ModelSession& s, const std::string& method, std::size_t samples,
             double tolerance, std::uint64_t seed, int threads,
             const std::vector<std::string>& cases) {
            CalibrateRequest q{method, samples, tolerance, seed, threads, cases};
            std::string text;
            {
              py::gil_scoped_release release;
              text = s.calibrate(q).dump();
            }
            return json_to_python(text);
          },
          py::arg("method") = "lm", py::arg("samples") = 0, py::arg("tolerance") = 5.0,
          py::arg("seed") = 1, py::arg("threads") = 0,
          py::arg("cases") = std::vector<std::string>{},
          "Fits the ranged params to the cases' data; returns the `calibrate --json` report.")
      .def(
          "diagnose",
          [](const ModelSession& s, const std::vector<std::string>& cases, int threads,
             std::size_t top) {
            std::string text;
            {
              py::gil_scoped_release release;
              text = s.diagnose(cases, threads, top).dump();
            }
            return json_to_python(text);
          },
          py::arg("cases") = std::vector<std::string>{}, py::arg("threads") = 0, py::arg("top") = 5,
          "What the model gets wrong; returns the `diagnose --json` report.")
      .def(
          "sensitivity",
          [](const ModelSession& s, const std::vector<std::string>& cases, bool elements,
             int threads) {
            std::string text;
            {
              py::gil_scoped_release release;
              text = s.sensitivity(cases, elements, threads).dump();
            }
            return json_to_python(text);
          },
          py::arg("cases") = std::vector<std::string>{}, py::arg("elements") = false,
          py::arg("threads") = 0, "Ranks the params; returns the `sensitivity --json` report.")
      .def("__repr__", [](const ModelSession& s) {
        return fmt::format("<thermnet.Model {} ({} nodes, {} cases)>", s.model().name(),
                           s.model().nodes().size(), s.model().cases().size());
      });
}
