"""monohydra from Python: open a model, set its inputs between steps, read any
value, run it to a NumPy table, save and restore the whole run.

    import monohydra
    res = monohydra.Simulation("models/fourbar.yaml").run()
    res["z1"], res.t            # float64 NumPy arrays
    res.to_csv("fourbar.csv")   # exactly `monohydra run`'s CSV

A thin layer over the embedding API (docs/embedding.md, docs/python.md):
every call that steps releases the GIL, so one Simulation per thread runs
in parallel. Errors raise monohydra.Error: InputError for a model, a name or
a value that is wrong (nothing changed), SimulationError for a step that
failed (the run keeps its last accepted state; restore a snapshot to go on),
with the command line's messages (file:line included).
"""

import os
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

__all__ = [
    "Simulation",
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
        return isinstance(other, Snapshot) and self.data == other.data

    def __hash__(self):
        return hash(self.data)

    def __repr__(self):
        return f"<monohydra.Snapshot of {len(self.data)} bytes>"


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
        self._run.set(self._index(name), float(value))

    def value(self, name: str) -> float:
        """Any variable's value at the last accepted step, by name."""
        return self._run.get(self._index(name))

    def start(self) -> None:
        self._run.start()

    def step(self, n: int = 1) -> None:
        """n steps of dt (the GIL released)."""
        self._run.step(int(n))

    def advance(self, t: float) -> None:
        """Steps until the time reaches t."""
        self._run.advance(float(t))

    def run(self, t_end: Optional[float] = None) -> Results:
        """Steps from the current state to t_end (default: the model's),
        returning the rows `monohydra run` writes from here on."""
        values, texts = self._run.rows_to(self.t_end if t_end is None else float(t_end))
        columns = self._run.row_names()
        units = {}
        for name in columns:
            v = self._by_name.get(name)
            units[name] = v.unit if v else _ROW_UNITS.get(name, "")
        return Results(columns, units, values, self._run.header(), texts)

    # Snapshots.
    def snapshot(self) -> Snapshot:
        return Snapshot(self._run.snapshot())

    def restore(self, snapshot: Snapshot) -> None:
        self._run.restore(snapshot.data)


_ROW_UNITS = {"t": "s", "KE": "J", "PE": "J", "W": "J", "drift": "J", "phi_norm": "", "iters": ""}
