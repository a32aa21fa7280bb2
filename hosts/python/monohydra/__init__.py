"""monohydra from Python: open a model, set its inputs between steps, read any
value, run it to a NumPy table, save and restore the whole run.

    import monohydra
    res = monohydra.Simulation("models/fourbar.yaml").run()
    res["z1"], res.t            # float64 NumPy arrays
    res.to_csv("fourbar.csv")   # exactly `monohydra run`'s CSV
    monohydra.compare("models/fourbar.yaml", formulations=["double-step", "penalty"])

A thin layer over the embedding API (docs/embedding.md, docs/python.md):
every call that steps releases the GIL, so one Simulation per thread runs
in parallel. Errors raise monohydra.Error: InputError for a model, a name or
a value that is wrong (nothing changed), SimulationError for a step that
failed (the run keeps its last accepted state; restore a snapshot to go on),
with the command line's messages (file:line included).
"""

import csv
import os
import shutil
import subprocess
import tempfile
import time as _time
import warnings
from typing import Dict, List, NamedTuple, Optional, Union

import numpy as np

from ._monohydra import (
    API_VERSION,
    COORDINATE,
    COORDINATE_RATE,
    INPUT,
    OUTPUT,
    STATE,
    Error,
    InputError,
    SimulationError,
    _Run,
)

for _error in (Error, InputError, SimulationError):
    _error.__module__ = "monohydra"  # shown as monohydra.InputError, where users catch it


class ModelWarning(UserWarning):
    """What a model's plugins warned of, or an input clamped to its range."""


def _warn(message: str) -> None:
    """A call's warning ("": none) through Python's warnings module."""
    if message:
        warnings.warn(message, ModelWarning, stacklevel=3)

__all__ = [
    "Simulation",
    "Linearization",
    "ModelWarning",
    "Batch",
    "BatchSnapshot",
    "RunStatus",
    "RunStoppedWarning",
    "Estimator",
    "compare",
    "sweep",
    "sensitivities",
    "fit",
    "Results",
    "Snapshot",
    "Variable",
    "Error",
    "InputError",
    "SimulationError",
    "API_VERSION",
]

_KINDS = {
    COORDINATE: "coordinate",
    COORDINATE_RATE: "coordinate rate",
    STATE: "state",
    OUTPUT: "output",
    INPUT: "input",
}


class Variable(NamedTuple):
    """A variable of a run: its name (the CSV column's where it has one), kind,
    SI unit and declared range (None when it declares none)."""

    name: str
    kind: str
    unit: str
    range: Optional[tuple]
    qualified: str


class Linearization(NamedTuple):
    """A run's state-space matrices (Simulation.linearize): float64 NumPy
    arrays A (n x n), B (n x m), C (p x n), D (p x m), the time t (s) they
    were taken at, and the names and SI units of the states X, inputs u and
    outputs Y."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    t: float
    states: List[str]
    state_units: List[str]
    inputs: List[str]
    input_units: List[str]
    outputs: List[str]
    output_units: List[str]


class Snapshot:
    """The whole state of a run between two steps, as the bytes the embedding
    API writes: restore it into a Simulation of the same model (in this process
    or, pickled, in another)."""

    __slots__ = ("data",)

    def __init__(self, data: bytes):
        self.data = bytes(data)

    def __getstate__(self):
        return self.data

    def __setstate__(self, data):
        self.data = data

    def __eq__(self, other):
        return type(other) is type(self) and self.data == other.data

    def __hash__(self):
        return hash(self.data)

    def __repr__(self):
        return f"<monohydra.{type(self).__name__} of {len(self.data)} bytes>"


class Results:
    """The rows a run wrote: each column a float64 NumPy array by its CSV name
    (``res["p1"]``), ``res.t`` the times; ``to_csv`` writes `monohydra run`'s
    CSV, byte for byte."""

    def __init__(self, columns, units, values, header, texts):
        self.columns: List[str] = list(columns)
        self.units: Dict[str, str] = dict(units)
        self._values = values
        self._header = header
        self._texts = texts
        self._index = {name: k for k, name in enumerate(self.columns)}

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._values[:, self._index[name]]
        except KeyError:
            raise KeyError(
                f"no column '{name}' (the run writes: {', '.join(self.columns)})"
            ) from None

    def __contains__(self, name):
        return name in self._index

    def __len__(self):
        return self._values.shape[0]

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    def to_csv(self, path: Union[str, os.PathLike]) -> None:
        with open(path, "w", encoding="utf-8", newline="") as out:
            out.write(self._header)
            out.writelines(self._texts)

    def __repr__(self):
        return f"<monohydra.Results: {len(self)} rows x {len(self.columns)} columns>"


def _text(value) -> str:
    """A setting's text: floats exactly (repr is the shortest round trip)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


class Simulation:
    """A run of a model.

    model: a path to a model file, or its YAML text. formulation, integrator,
    dt, t_end replace the file's; options maps option paths (as `monohydra
    sweep` addresses them: "subsystems/valve/flow_coefficient") to values.
    """

    def __init__(
        self,
        model: Union[str, os.PathLike],
        formulation: Optional[str] = None,
        integrator: Optional[str] = None,
        dt: Optional[float] = None,
        t_end: Optional[float] = None,
        options: Optional[Dict[str, object]] = None,
    ):
        settings = []
        for key, value in (
            ("formulation", formulation),
            ("integrator", integrator),
            ("dt", dt),
            ("t_end", t_end),
        ):
            if value is not None:
                settings.append((key, _text(value)))
        for path, value in (options or {}).items():
            settings.append((str(path), _text(value)))
        text = os.fspath(model)
        if "\n" in text:
            self._run = _Run.open_text(text, "<text>", os.getcwd(), settings)
        else:
            self._run = _Run.open_file(text, settings)
        _warn(self._run.warning())
        self._variables = [
            Variable(name, _KINDS.get(kind, str(kind)), unit,
                     (lo, hi) if lo <= hi else None, qualified)
            for kind, name, qualified, unit, lo, hi in self._run.variables()
        ]
        self._by_name = {}
        for v in self._variables:
            self._by_name.setdefault(v.name, v)
        self._indices: Dict[str, int] = {}

    # What the model has.
    def _of(self, kind):
        return [v for v in self._variables if v.kind == kind]

    @property
    def inputs(self) -> List[Variable]:
        return self._of("input")

    @property
    def outputs(self) -> List[Variable]:
        return self._of("output")

    @property
    def states(self) -> List[Variable]:
        return self._of("state")

    @property
    def coordinates(self) -> List[Variable]:
        return self._of("coordinate")

    @property
    def columns(self) -> List[str]:
        """The CSV columns `monohydra run` writes for this model."""
        return self._run.row_names()

    @property
    def time(self) -> float:
        return self._run.time

    @property
    def steps(self) -> int:
        return self._run.steps

    @property
    def dt(self) -> float:
        return self._run.dt

    @property
    def t_end(self) -> float:
        return self._run.t_end

    def _index(self, name: str) -> int:
        index = self._indices.get(name)
        if index is None:
            index = self._indices[name] = self._run.find(name)
        return index

    # Between two steps.
    def set_input(self, name: str, value: float) -> None:
        """Sets one of the model's inputs from now on (a change is a jump at
        the current time); refused (InputError) when not finite or outside its
        declared range, unless the input clamps."""
        _warn(self._run.set(self._index(name), float(value)))

    def set_parameter(self, path: str, value: float) -> None:
        """Changes a value of the model in place, before start or between
        steps, without opening it again: a body's mass, centre of mass or
        inertia, or gravity, by its path ("bodies/body3/mass", "gravity/1"),
        in the model file's units. The run goes on from its state as a run
        of the changed model. Refused (InputError), nothing changed: a path
        the model does not have, a component's option (open the model with
        options={path: value} instead), a value the model file refuses."""
        self._run.set_parameter(str(path), float(value))

    def track_sensitivities(self, params: List[str]) -> None:
        """Before the run starts: from then on every step also carries the
        derivatives of its values with respect to `params` (paths as
        set_parameter names them, "subsystems/valve/flow_coefficient"
        included), read with sensitivity(name). Refused (InputError): after
        the start, a path that is not such a parameter, a run that cannot
        carry them (an explicit integrator, ...)."""
        if isinstance(params, str) or not params:
            raise InputError("track_sensitivities: params is a non-empty list of paths")
        self._run.track_sensitivities([str(p) for p in params])

    def sensitivity(self, name: str) -> np.ndarray:
        """d(name)/d(parameter) at the last accepted step, one float64 per
        parameter tracked, in their order (NaN for a value without one: an
        input)."""
        return np.array(self._run.sensitivities(self._index(name)), dtype=np.float64)

    def value(self, name: str) -> float:
        """Any variable's value at the last accepted step, by name."""
        return self._run.get(self._index(name))

    def start(self) -> None:
        _warn(self._run.start())

    def step(self, n: int = 1) -> None:
        """n steps of dt (the GIL released; Ctrl-C stops it between two steps)."""
        _warn(self._run.step(int(n)))

    def advance(self, t: float) -> None:
        """Steps until the time reaches t (Ctrl-C stops it between two steps)."""
        _warn(self._run.advance(float(t)))

    def run(self, t_end: Optional[float] = None) -> Results:
        """Steps from the current state to t_end (default: the model's),
        returning the rows `monohydra run` writes from here on. A step that
        fails raises SimulationError whose `results` holds the rows before
        it; a t_end whose rows would not fit in memory raises InputError."""
        values, texts, failed, warned = self._run.rows_to(
            self.t_end if t_end is None else float(t_end))
        _warn(warned)
        columns = self._run.row_names()
        units = {}
        for name in columns:
            v = self._by_name.get(name)
            units[name] = v.unit if v else _ROW_UNITS.get(name, "")
        results = Results(columns, units, values, self._run.header(), texts)
        if failed:
            error = SimulationError(failed)
            error.results = results
            raise error
        return results

    def linearize(self, outputs: List[str]) -> "Linearization":
        """The state-space matrices about the last accepted state,
        dX/dt = A X + B u, Y = C X + D u, over the model's inputs u and the
        values named in `outputs` (coordinates, rates, states, outputs); the
        run goes on as if it had not been asked (docs/embedding.md)."""
        a, b, c, d, t, states, sunits, inputs, iunits, outs, ounits = self._run.linearize(
            [str(o) for o in outputs])
        return Linearization(a, b, c, d, t, states, sunits, inputs, iunits, outs, ounits)

    # Snapshots.
    def snapshot(self) -> Snapshot:
        return Snapshot(self._run.snapshot())

    def restore(self, snapshot: Snapshot) -> None:
        """The run back to the snapshot's state; a ModelWarning names any value
        changed in place (a mass, gravity) that differs from the snapshot's."""
        self._run.restore(snapshot.data)
        _warn(self._run.warning())


class Estimator:
    """A Kalman filter that keeps a Simulation on a running machine
    (docs/estimation.md): each update(t, readings) steps the run to t (the
    filter's prediction) and corrects it with the readings of the model's
    sensors (its sensors: list), so that every value sim.value() reads is
    the estimate.

        sim = monohydra.Simulation("models/fourbar.yaml")
        est = monohydra.Estimator(sim)
        est.update(0.001, {"z1": 0.0123})        # sensors without a sample left out
        est["p1"], est.sd("p1"), sim.value("s")  # a state, its sd, any value

    filter: "ekf" (the extended filter on the step's own map) or "ukf" (the
    unscented). params: paths estimated beside the state
    ("subsystems/valve/flow_coefficient"). plant_noise and initial_sd map a
    state's name or a parameter's path to a standard deviation (the error
    it gains in a second; the initial error) where the defaults will not
    do. Refused (InputError): a model without sensors, an unknown filter,
    path or name, a negative noise. An update that the filter cannot take
    (it diverges; the run's step fails) raises SimulationError, and the
    filter takes no more.
    """

    def __init__(
        self,
        sim: "Simulation",
        filter: str = "ekf",
        params: Optional[List[str]] = None,
        plant_noise: Optional[Dict[str, float]] = None,
        initial_sd: Optional[Dict[str, float]] = None,
    ):
        if not isinstance(sim, Simulation):
            raise InputError("Estimator: sim is a monohydra.Simulation")
        if isinstance(params, str):
            raise InputError("Estimator: params is a list of paths, not one string")
        plant_noise = dict(plant_noise or {})
        initial_sd = dict(initial_sd or {})
        names = list(dict.fromkeys([*plant_noise, *initial_sd]))
        nan = float("nan")
        self._sim = sim
        self._filter = sim._run.estimator(
            str(filter),
            [str(p) for p in (params or [])],
            [str(n) for n in names],
            [float(plant_noise.get(n, nan)) for n in names],
            [float(initial_sd.get(n, nan)) for n in names],
        )
        self.states: List[str] = self._filter.states()
        self.units: Dict[str, str] = dict(zip(self.states, self._filter.units()))
        self.sensors: List[str] = self._filter.sensors()
        self._state_index = {name: k for k, name in enumerate(self.states)}
        self._sensor_index = {name: k for k, name in enumerate(self.sensors)}

    def update(self, t: float, readings: Dict[str, float]) -> None:
        """The readings taken at time t (s) by sensor name; a sensor left out
        (or None) took no sample. Refused (InputError): a name that is not a
        sensor, a value that is not a finite number, t before the run's
        step."""
        values = [float("nan")] * len(self.sensors)
        for name, value in dict(readings).items():
            k = self._sensor_index.get(name)
            if k is None:
                raise InputError(
                    f"Estimator.update: '{name}' is not a sensor of the model "
                    f"({', '.join(self.sensors)})"
                )
            if value is None:
                continue
            v = float(value)
            if not np.isfinite(v):
                raise InputError(
                    f"Estimator.update: sensor '{name}': {value!r} is not a finite number "
                    "(leave a sensor out for no sample)"
                )
            values[k] = v
        t = float(t)
        if not np.isfinite(t):
            raise InputError(f"Estimator.update: t = {t!r} is not a finite time")
        # The step nearest t, halves away from zero as the library rounds.
        if np.sign(t) * np.floor(abs(t) / self._sim.dt + 0.5) < self._sim.steps:
            raise InputError(
                f"Estimator.update: t = {t!r} s falls before the run's step at "
                f"{self._sim.time!r} s"
            )
        self._filter.update(t, values)

    @property
    def state(self) -> np.ndarray:
        """The estimate of the filter's states (names: .states)."""
        return np.array(self._filter.state(), dtype=np.float64)

    @property
    def covariance(self) -> np.ndarray:
        """The states' covariance, n x n."""
        return self._filter.covariance()

    def _state(self, name: str) -> int:
        k = self._state_index.get(name)
        if k is None:
            raise KeyError(f"no state '{name}' (the filter's: {', '.join(self.states)})")
        return k

    def __getitem__(self, name: str) -> float:
        """A state's (or an estimated parameter's) estimate by name."""
        return float(self._filter.state()[self._state(name)])

    def sd(self, name: str) -> float:
        """A state's (or parameter's) standard deviation by name."""
        k = self._state(name)
        return float(np.sqrt(self.covariance[k, k]))

    @property
    def innovation(self) -> Dict[str, float]:
        """Of the last update, per sensor: reading - model's reading - bias
        (NaN without a sample)."""
        return dict(zip(self.sensors, self._filter.innovation()))

    @property
    def innovation_sd(self) -> Dict[str, float]:
        return dict(zip(self.sensors, self._filter.innovation_sd()))

    @property
    def nis(self) -> float:
        """The last update's normalised innovation squared (NaN: no sample)."""
        return self._filter.nis()

    def __repr__(self):
        return (
            f"<monohydra.Estimator: {len(self.states)} states, "
            f"{len(self.sensors)} sensors, t = {self._sim.time!r} s>"
        )


_ROW_UNITS = {"t": "s", "KE": "J", "PE": "J", "W": "J", "drift": "J", "phi_norm": "", "iters": ""}


def _metrics(res: Results, wall: float, dt: float) -> dict:
    """The comparison table's numbers of one run (docs/compare.md), from its
    rows as `monohydra compare` computes them."""
    t, iters, drift, work = res.t, res["iters"], res["drift"], res["W"]
    steps = len(res) - 1
    peak = int(np.argmax(np.abs(drift)))
    max_work = float(np.max(np.abs(work)))
    return {
        "steps": int(round(t[-1] / dt)),
        "avg_iterations": float(np.mean(iters[1:])) if steps > 0 else 0.0,
        "max_iterations": int(np.max(iters[1:])) if steps > 0 else 0,
        "wall_seconds": wall,
        "peak_abs_drift": float(abs(drift[peak])),
        "peak_drift_time": float(t[peak]),
        "max_abs_work": max_work,
        "drift_percent": float(abs(drift[peak]) / max_work * 100.0) if max_work > 0 else None,
        "max_phi_norm": float(np.max(res["phi_norm"])),
    }


def compare(
    model: Union[str, os.PathLike],
    formulations: Optional[List[str]] = None,
    integrators: Optional[List[str]] = None,
    dt: Optional[float] = None,
    t_end: Optional[float] = None,
) -> List[dict]:
    """Every formulation with every integrator on the model (None: the model
    file's own), as `monohydra compare` runs them: one dict per run with its
    table's numbers (steps, avg_iterations, max_iterations, wall_seconds,
    peak_abs_drift, peak_drift_time, max_abs_work, drift_percent,
    max_phi_norm) and, against the first run (the reference), max_abs_dz and
    max_abs_dp (per pressure state). A run that fails has status "failed" and
    its reason; the others "ok"."""
    table, reference = [], None
    for formulation in formulations or [None]:
        for integrator in integrators or [None]:
            sim = Simulation(model, formulation=formulation, integrator=integrator, dt=dt,
                             t_end=t_end)
            entry = {"formulation": formulation, "integrator": integrator}
            start = _time.perf_counter()
            try:
                res = sim.run()
            except SimulationError as err:
                entry.update(status="failed", reason=str(err))
                table.append(entry)
                continue
            entry.update(status="ok", **_metrics(res, _time.perf_counter() - start, sim.dt))
            pressures = [v.name for v in sim.states if v.unit == "Pa" and v.name in res]
            if reference is None:
                reference = (res, sim.coordinates, pressures)
            ref, coordinates, _ = reference
            rows = min(len(res), len(ref))
            entry["max_abs_dz"] = max(
                (float(np.max(np.abs(res[c.name][:rows] - ref[c.name][:rows])))
                 for c in coordinates if c.name in res and c.name in ref), default=None)
            entry["max_abs_dp"] = {
                p: float(np.max(np.abs(res[p][:rows] - ref[p][:rows])))
                for p in pressures if p in ref}
            table.append(entry)
    return table


def _command_line() -> str:
    """The monohydra executable beside this module's build or install."""
    here = os.path.dirname(os.path.abspath(__file__))
    for candidate in (
        os.environ.get("MONOHYDRA_EXECUTABLE", ""),
        os.path.join(here, "..", "..", "bin", "monohydra"),              # build/python/monohydra
        os.path.join(here, "..", "..", "..", "..", "bin", "monohydra"),  # lib/python3.X/dist-packages
    ):
        if candidate and os.access(candidate, os.X_OK):
            return os.path.normpath(candidate)
    found = shutil.which("monohydra")
    if found:
        return found
    raise Error("monohydra.sweep: the monohydra command was not found beside the module, on "
                "PATH or in MONOHYDRA_EXECUTABLE")


def sweep(study: Union[str, os.PathLike], jobs: Optional[int] = None,
          out: Optional[Union[str, os.PathLike]] = None) -> Dict[str, np.ndarray]:
    """Runs a study file's cases as `monohydra sweep` does (on `jobs` local
    workers; into `out`, a temporary folder when None) and returns its table
    DIR/results.csv: one entry per column, numbers as float64 NumPy arrays
    (empty cells NaN), text columns (a failed case's reason) as lists."""
    folder = os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="monohydra-sweep-")
    command = [_command_line(), "sweep", os.fspath(study), "--out", folder]
    if jobs is not None:
        command += ["--jobs", str(int(jobs))]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        message = (done.stderr or done.stdout).strip()
        raise (InputError if done.returncode == 2 else SimulationError)(message)
    with open(os.path.join(folder, "results.csv"), newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if out is None:
        shutil.rmtree(folder, ignore_errors=True)
    table: Dict[str, object] = {}
    for name in (rows[0].keys() if rows else []):
        cells = [r[name] for r in rows]
        try:
            table[name] = np.array([float(c) if c != "" else np.nan for c in cells])
        except ValueError:
            table[name] = cells
    return table


def sensitivities(model: Union[str, os.PathLike], params: List[str],
                  formulation: Optional[str] = None, integrator: Optional[str] = None,
                  dt: Optional[float] = None, t_end: Optional[float] = None,
                  options: Optional[Dict[str, object]] = None) -> Dict[str, np.ndarray]:
    """The forward sensitivities of a run of the model file `model` with
    respect to `params` (paths as `options` names them: "bodies/body3/mass",
    "subsystems/valve/flow_coefficient"), as `monohydra sensitivities`
    computes them (docs/identification.md): one float64 array per column,
    "t" and "d(NAME)/d(PATH)" for every coordinate, named state and output
    and every parameter, one entry per step."""
    if isinstance(params, str) or not params:
        raise InputError("sensitivities: params is a non-empty list of paths")
    fd, path = tempfile.mkstemp(prefix="monohydra-sensitivities-", suffix=".csv")
    os.close(fd)
    command = [_command_line(), "sensitivities", os.fspath(model), "--params", ",".join(params),
               "--out", path]
    for flag, value in (("--formulation", formulation), ("--integrator", integrator),
                        ("--dt", dt), ("--t-end", t_end)):
        if value is not None:
            command += [flag, _text(value)]
    for key, value in (options or {}).items():
        command += ["--set", key + "=" + _text(value)]
    try:
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            message = (done.stderr or done.stdout).strip()
            raise (InputError if done.returncode == 2 else SimulationError)(message)
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            names = next(reader)
            values = np.array([[float(c) for c in row] for row in reader], dtype=np.float64)
    finally:
        os.remove(path)
    values = values.reshape(-1, len(names))
    return {name: values[:, i] for i, name in enumerate(names)}


def fit(model: Union[str, os.PathLike], data: Union[str, os.PathLike, Dict[str, object]],
        params: List[str], noise: Optional[Dict[str, float]] = None,
        formulation: Optional[str] = None, integrator: Optional[str] = None,
        dt: Optional[float] = None, t_end: Optional[float] = None,
        options: Optional[Dict[str, object]] = None,
        out: Optional[Union[str, os.PathLike]] = None) -> Dict[str, np.ndarray]:
    """Fits `params` (paths as `options` names them) of the model file `model`
    to measured data as `monohydra fit` does (docs/identification.md).
    `data` is a CSV file's path, or a mapping of "t" and column names to
    equal-length sequences (NaN: a sample not taken). `noise` maps a column
    to its standard deviation. Returns one entry per column of
    estimates.csv, one element per parameter: "path" (str), "initial",
    "estimate", "std_error", "ci_low", "ci_high" (float64; NaN where not
    identifiable) and "identifiable" (bool). `out`: a folder that keeps
    estimates.csv, fitted.yaml and report.html. Bad input raises InputError;
    a fit that fails, SimulationError."""
    if isinstance(params, str) or not params:
        raise InputError("fit: params is a non-empty list of paths")
    scratch = tempfile.mkdtemp(prefix="monohydra-fit-")
    try:
        if isinstance(data, (str, os.PathLike)):
            data_path = os.fspath(data)
        else:
            if "t" not in data:
                raise InputError("fit: data has no \"t\" (the samples' times, s)")
            names = ["t"] + [n for n in data if n != "t"]
            columns = [np.asarray(data[n], dtype=np.float64).ravel() for n in names]
            if any(c.shape != columns[0].shape for c in columns):
                raise InputError("fit: data's columns differ in length")
            data_path = os.path.join(scratch, "data.csv")
            with open(data_path, "w", newline="", encoding="utf-8") as f:
                f.write(",".join(names) + "\n")
                for row in zip(*columns):
                    f.write(",".join("" if np.isnan(v) else repr(float(v)) for v in row) + "\n")
        folder = os.fspath(out) if out is not None else os.path.join(scratch, "fit")
        command = [_command_line(), "fit", os.fspath(model), "--data", data_path,
                   "--params", ",".join(params), "--out", folder]
        for flag, value in (("--formulation", formulation), ("--integrator", integrator),
                            ("--dt", dt), ("--t-end", t_end)):
            if value is not None:
                command += [flag, _text(value)]
        for key, value in (noise or {}).items():
            command += ["--noise", key + "=" + _text(value)]
        for key, value in (options or {}).items():
            command += ["--set", key + "=" + _text(value)]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            message = (done.stderr or done.stdout).strip()
            failed = done.returncode == 1 and message.startswith("monohydra: fit:")
            raise (SimulationError if failed else InputError)(message)
        with open(os.path.join(folder, "estimates.csv"), newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader)
            rows = list(reader)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    result: Dict[str, np.ndarray] = {"path": np.array([r[0] for r in rows], dtype=object)}
    for i, name in enumerate(header[1:6], start=1):
        result[name] = np.array([float(r[i]) if r[i] else np.nan for r in rows], dtype=np.float64)
    result["identifiable"] = np.array([r[6] == "1" for r in rows], dtype=bool)
    return result

from .batch import Batch, BatchSnapshot, RunStatus, RunStoppedWarning  # noqa: E402

for _name in ("Batch", "BatchSnapshot", "RunStatus", "RunStoppedWarning"):
    globals()[_name].__module__ = "monohydra"
