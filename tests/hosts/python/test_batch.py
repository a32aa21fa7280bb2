"""monohydra.Batch: each run of a batch stepped on two threads is that run
stepped alone to the bit; a run whose step fails stops alone and a warning
names it; Ctrl-C stops a long advance between two steps; a snapshot puts
every run back; each run takes its own input; bad arguments raise
InputError naming them."""

import os
import pickle
import signal
import threading
import warnings

import numpy as np
import pytest

import monohydra

SOURCE = os.environ["MH_SOURCE_DIR"]
FOURBAR = os.path.join(SOURCE, "models", "fourbar.yaml")
FLOW = "subsystems/valve/flow_coefficient"
MASS = "bodies/body3/mass"
BULK = "subsystems/cylinder/fluid_bulk_modulus"


def randomised(n):
    rng = np.random.default_rng(20261207)
    f = rng.uniform(0.8, 1.2, size=(n, 3))
    return [{FLOW: 2.138e-8 * a, MASS: 50.0 * b, BULK: 1.5e9 * c} for a, b, c in f]


def test_each_run_is_that_run_stepped_alone_to_the_bit():
    options = randomised(4)
    batch = monohydra.Batch(FOURBAR, options=options, threads=2)
    assert batch.runs == 4 and batch.threads == 2
    batch.advance(1.5)
    names = [v.name for v in monohydra.Simulation(FOURBAR)._variables]
    together = {name: batch.value(name) for name in names}
    assert together["z1"][0] != together["z1"][1]  # the parameters move the runs
    for k, params in enumerate(options):
        alone = monohydra.Simulation(FOURBAR)
        for path, value in params.items():
            alone.set_parameter(path, value)
        alone.advance(1.5)
        for name in names:
            assert together[name][k].tobytes() == np.float64(alone.value(name)).tobytes(), (
                f"run {k}, {name}"
            )


def test_a_failing_run_stops_alone_and_a_warning_names_it_once():
    batch = monohydra.Batch(FOURBAR, options=[{}, {FLOW: 2e-5}, {}])
    with pytest.warns(monohydra.RunStoppedWarning, match=r"1 of 3 runs stopped[\s\S]*run 1: t = 1\.001 s"):
        batch.advance(1.2)
    status = batch.status()
    assert [s.stopped for s in status] == [False, True, False]
    assert status[1].steps == 1000 and "Newton did not converge" in status[1].reason
    assert list(batch.time) == pytest.approx([1.2, 1.0, 1.2])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # named once: no second warning
        batch.advance(1.3)
    assert list(batch.time) == pytest.approx([1.3, 1.0, 1.3])
    # A batch whose every run stopped advances nothing, and says nothing new.
    alone = monohydra.Batch(FOURBAR, options=[{FLOW: 2e-5}])
    with pytest.warns(monohydra.RunStoppedWarning):
        alone.advance(1.2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        alone.advance(1.5)
    assert alone.status()[0].stopped and alone.status()[0].time == pytest.approx(1.0)


def test_ctrl_c_stops_a_long_advance_between_two_steps():
    batch = monohydra.Batch(FOURBAR, runs=2, threads=2)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            batch.advance(1e6)  # days of model time: only Ctrl-C ends it
    finally:
        timer.cancel()
    status = batch.status()
    assert all(not s.stopped for s in status)
    assert 0.0 < status[0].time < 1e3
    # At a step, and it goes on from there.
    assert status[0].steps == round(status[0].time / batch.dt)
    t = status[0].time
    batch.advance(t + 0.01)
    assert list(batch.time) == pytest.approx([t + 0.01] * 2)


def test_a_snapshot_repeats_every_run_to_the_bit_here_and_pickled_in_another_batch():
    options = [{MASS: 40.0}, {MASS: 60.0}]
    batch = monohydra.Batch(FOURBAR, options=options)
    batch.advance(0.9)
    snap = batch.snapshot()
    batch.advance(1.4)
    first = batch.value("p2")
    batch.restore(snap)
    assert list(batch.time) == pytest.approx([0.9, 0.9])
    batch.advance(1.4)
    assert batch.value("p2").tobytes() == first.tobytes()
    # Pickled, into another batch of the same model and parameters.
    other = monohydra.Batch(FOURBAR, options=options)
    other.restore(pickle.loads(pickle.dumps(snap)))
    other.advance(1.4)
    assert other.value("p2").tobytes() == first.tobytes()
    # Into a batch of other masses: restored, and a warning names them.
    lighter = monohydra.Batch(FOURBAR, options=[{MASS: 40.0}, {MASS: 45.0}])
    with pytest.warns(monohydra.ModelWarning, match="run 1: body 'body3' mass 45 kg in this run"):
        lighter.restore(snap)
    with pytest.raises(monohydra.InputError, match="the bytes hold 2 runs, the batch has 3"):
        monohydra.Batch(FOURBAR, runs=3).restore(snap)


def test_each_run_takes_its_own_input():
    batch = monohydra.Batch(FOURBAR, runs=2)
    batch.advance(0.2)
    before = batch.value("z1")
    batch.set_input("valve_command", [5.0, -5.0])
    assert list(batch.value("valve_command")) == [5.0, -5.0]
    batch.advance(0.5)
    moved = batch.value("z1") - before
    assert moved[0] * moved[1] < 0.0
    with pytest.raises(monohydra.InputError, match="run 1: "):
        batch.set_input("valve_command", [0.0, 1e3])
    assert list(batch.value("valve_command")) == [5.0, -5.0]


def test_bad_arguments_raise_input_error_naming_them():
    with pytest.raises(TypeError, match="options"):
        monohydra.Batch(FOURBAR)
    with pytest.raises(ValueError, match="at least one run"):
        monohydra.Batch(FOURBAR, options=[])
    with pytest.raises(ValueError, match="threads=0"):
        monohydra.Batch(FOURBAR, runs=2, threads=0)
    with pytest.raises(monohydra.InputError, match="nonexistent"):
        monohydra.Batch(os.path.join(SOURCE, "models", "nonexistent.yaml"), runs=2)
    with pytest.raises(monohydra.InputError, match="run 1: .*body9"):
        monohydra.Batch(FOURBAR, options=[{}, {"bodies/body9/mass": 1.0}])
    batch = monohydra.Batch(FOURBAR, runs=2)
    with pytest.raises(monohydra.InputError, match="no value 'nothing'"):
        batch.value("nothing")
    with pytest.raises(monohydra.InputError, match="'z1' is not an input"):
        batch.set_input("z1", 0.0)
    with pytest.raises(TypeError, match="BatchSnapshot"):
        batch.restore(b"bytes")
