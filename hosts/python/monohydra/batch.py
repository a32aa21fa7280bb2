"""Many runs of one model stepped together: monohydra.Batch.

    import monohydra
    b = monohydra.Batch("models/fourbar.yaml",
                        options=[{"bodies/body3/mass": m} for m in (40, 50, 60)])
    b.advance(2.0)
    b.value("z1")        # a NumPy array, one entry per run
    b.status()           # each run's RunStatus

The model is read and its plugins loaded once for every run; each run has
its own parameters (its dict of options: paths as Simulation.set_parameter
takes them) and its own inputs. Stepping releases the GIL and runs on the
batch's threads; each run's result is the one it would have stepped alone,
to the bit. A run whose step fails stops alone: the others go on, a
monohydra.RunStoppedWarning names it, and status() keeps its time and
reason. Ctrl-C stops a long advance between two steps (KeyboardInterrupt).
"""

import os
import warnings
from typing import Dict, List, NamedTuple, Optional, Sequence, Union

import numpy as np

from . import Snapshot
from ._monohydra import _Batch


class RunStoppedWarning(RuntimeWarning):
    """Runs of a batch stopped (a step failed); the others went on."""


class RunStatus(NamedTuple):
    """One run of a batch: whether it stopped, the time (s) and step count of
    its last accepted state, and why it stopped ("" when it did not)."""

    stopped: bool
    time: float
    steps: int
    reason: str


class BatchSnapshot(Snapshot):
    """Every run's whole state (Batch.snapshot), as bytes: picklable, and
    restored into a batch of as many runs of the same model, in this process
    or another of the same build. A Snapshot's bytes, of a batch."""

    __slots__ = ()


class Batch:
    """Runs of a model, stepped together.

    model: a path to a model file, or its YAML text. options: one dict per
    run of values changed in place (paths as Simulation.set_parameter takes
    them: "bodies/body3/mass", "subsystems/valve/flow_coefficient"), or runs:
    that many runs of the model as it is. threads: how many in all (None:
    one per core). formulation, integrator, dt, t_end replace the file's for
    every run.
    """

    def __init__(
        self,
        model: Union[str, os.PathLike],
        options: Optional[Sequence[Dict[str, float]]] = None,
        threads: Optional[int] = None,
        runs: Optional[int] = None,
        formulation: Optional[str] = None,
        integrator: Optional[str] = None,
        dt: Optional[float] = None,
        t_end: Optional[float] = None,
    ):
        from . import _text  # the package's exact text of a value

        if options is None and runs is None:
            raise TypeError("Batch: give options (one dict per run) or runs")
        if options is not None and runs is not None and runs != len(options):
            raise ValueError(f"Batch: runs={runs} but {len(options)} dicts of options")
        count = len(options) if options is not None else int(runs)
        if count < 1:
            raise ValueError("Batch: at least one run")
        if threads is not None and int(threads) < 1:
            raise ValueError(f"Batch: threads={threads}; at least 1 (None: one per core)")
        settings = [
            (key, _text(value))
            for key, value in (
                ("formulation", formulation),
                ("integrator", integrator),
                ("dt", dt),
                ("t_end", t_end),
            )
            if value is not None
        ]
        text = os.fspath(model)
        n_threads = 0 if threads is None else int(threads)
        if "\n" in text:
            self._batch = _Batch.open_text(text, "<text>", os.getcwd(), count, n_threads, settings)
        else:
            self._batch = _Batch.open_file(text, count, n_threads, settings)
        if self._batch.warning:
            warnings.warn(self._batch.warning, stacklevel=2)
        for k, run_options in enumerate(options or []):
            for path, value in run_options.items():
                self._batch.set_parameter(k, str(path), float(value))
        self._indices: Dict[str, int] = {}
        self._stopped: set = set()  # the runs a warning has named

    def __len__(self) -> int:
        return self._batch.runs

    @property
    def runs(self) -> int:
        return self._batch.runs

    @property
    def threads(self) -> int:
        return self._batch.threads

    @property
    def dt(self) -> float:
        return self._batch.dt

    @property
    def t_end(self) -> float:
        return self._batch.t_end

    @property
    def time(self) -> np.ndarray:
        """Each run's time (s) of its last accepted state."""
        return np.array([s.time for s in self.status()])

    def _index(self, name: str) -> int:
        if name not in self._indices:
            self._indices[name] = self._batch.find(name)
        return self._indices[name]

    def set_parameter(self, run: int, path: str, value: float) -> None:
        """A value of run `run`'s model changed in place, between steps."""
        self._batch.set_parameter(int(run), str(path), float(value))

    def _stepped(self, message: str) -> None:
        """One warning naming the runs that stopped in this call."""
        if not message:
            return
        lines = []
        for k, s in enumerate(self.status()):
            if s.stopped and k not in self._stopped:
                self._stopped.add(k)
                lines.append(f"run {k}: {s.reason}")
        if lines:
            warnings.warn(
                f"{len(lines)} of {self.runs} runs stopped (the others went on):\n"
                + "\n".join(lines),
                RunStoppedWarning,
                stacklevel=3,
            )

    def start(self) -> None:
        self._stepped(self._batch.start())

    def step(self, n: int = 1) -> None:
        """n steps of dt for every run that has not stopped."""
        self._stepped(self._batch.step(int(n)))

    def advance(self, t: float) -> None:
        """Every run that has not stopped steps until its time reaches t."""
        self._stepped(self._batch.advance(float(t)))

    def value(self, name: str) -> np.ndarray:
        """A variable of every run (one float64 per run), by name."""
        return self._batch.get(self._index(name))

    def set_input(self, name: str, values) -> None:
        """Input `name` of each run (one value per run, or one for all)."""
        v = np.broadcast_to(np.asarray(values, dtype=float), (self.runs,))
        message = self._batch.set(self._index(name), [float(x) for x in v])
        if message:
            warnings.warn(message, stacklevel=2)

    def status(self) -> List[RunStatus]:
        return [RunStatus(*s) for s in self._batch.status()]

    def snapshot(self) -> BatchSnapshot:
        return BatchSnapshot(self._batch.snapshot())

    def restore(self, snapshot: BatchSnapshot) -> None:
        """Every run back to the snapshot, stops forgotten."""
        if not isinstance(snapshot, BatchSnapshot):
            raise TypeError("restore: expected a BatchSnapshot of this batch")
        message = self._batch.restore(snapshot.data)
        self._stopped.clear()
        if message:
            from . import ModelWarning

            warnings.warn(message, ModelWarning, stacklevel=2)
