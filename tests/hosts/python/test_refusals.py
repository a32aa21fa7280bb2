"""What monohydra.Simulation refuses or says instead of failing silently:
Ctrl-C stops a long advance or step between two steps; a clamped input and
a plugin's warning reach Python's warnings module; a failed run() raises
SimulationError carrying the rows before the failure; a run() whose rows
would not fit in memory is refused before its first step."""

import os
import signal
import threading

import numpy as np
import pytest

import monohydra

SOURCE = os.environ["MH_SOURCE_DIR"]
FOURBAR = os.path.join(SOURCE, "models", "fourbar.yaml")


def interrupt_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("call", ["advance", "step"])
def test_ctrl_c_stops_a_long_call_between_two_steps(call):
    sim = monohydra.Simulation(FOURBAR)
    timer = interrupt_after(0.3)
    try:
        with pytest.raises(KeyboardInterrupt):
            if call == "advance":
                sim.advance(1e6)  # days of model time
            else:
                sim.step(10**9)
    finally:
        timer.cancel()
    assert 0.0 < sim.time < 1e3
    assert sim.steps == round(sim.time / sim.dt)  # at a step
    t = sim.time
    sim.advance(t + 0.01)  # and it goes on from there
    assert sim.time == pytest.approx(t + 0.01)


def test_a_clamped_input_warns_through_the_warnings_module():
    text = open(FOURBAR).read().replace(
        "    range: [-10, 10]\n", "    range: [-10, 10]\n    out_of_range: clamp\n")
    sim = monohydra.Simulation(text)
    sim.start()
    with pytest.warns(monohydra.ModelWarning, match="clamped to 10"):
        sim.set_input("valve_command", 25.0)
    assert sim.value("valve_command") == 10.0


def test_a_plugins_warning_at_open_warns_through_the_warnings_module():
    # The excavator's double-step formulation drops its redundant rows, and says so.
    with pytest.warns(monohydra.ModelWarning, match="redundant constraints"):
        monohydra.Simulation(os.path.join(SOURCE, "models", "excavator-ls.yaml"))


def test_a_failed_run_raises_with_the_rows_before_the_failure():
    sim = monohydra.Simulation(FOURBAR, options={"subsystems/valve/flow_coefficient": 2e-5})
    with pytest.raises(monohydra.SimulationError, match="t = 1.001 s") as caught:
        sim.run(2.0)
    rows = caught.value.results
    assert rows.t[0] == 0.0
    assert rows.t[-1] == pytest.approx(1.0)  # the last accepted step
    assert len(rows) == 1001
    assert np.all(np.isfinite(rows["z1"]))


def test_a_run_whose_rows_would_not_fit_is_refused_before_its_first_step():
    sim = monohydra.Simulation(FOURBAR)
    with pytest.raises(monohydra.InputError, match="more than run\\(\\) keeps"):
        sim.run(1e7)
    assert sim.steps == 0


def test_linearize_gives_the_spools_time_constant_and_leaves_the_run_as_it_was():
    sim = monohydra.Simulation(FOURBAR)
    twin = monohydra.Simulation(FOURBAR)
    sim.advance(0.5)
    twin.advance(0.5)
    lin = sim.linearize(["s", "z1_dot", "U"])
    n = len(lin.states)
    assert lin.A.shape == (n, n) and lin.B.shape == (n, 1)
    assert lin.C.shape == (3, n) and lin.D.shape == (3, 1)
    assert lin.inputs == ["valve_command"] and lin.input_units == ["V"]
    assert lin.outputs == ["s", "z1_dot", "U"] and lin.output_units[1] == "rad/s"
    assert lin.t == pytest.approx(0.5)
    spool = lin.states.index("U")
    tau = 4.547e-3  # the model's spool time constant
    assert lin.A[spool, spool] == pytest.approx(-1.0 / tau, rel=1e-4)
    assert lin.B[spool, 0] == pytest.approx(1.0 / tau, rel=1e-4)
    # The output U is the state U.
    assert lin.C[2, spool] == 1.0 and lin.D[2, 0] == 0.0
    sim.advance(1.5)
    twin.advance(1.5)
    assert sim.value("p2") == twin.value("p2")  # to the bit
    with pytest.raises(monohydra.InputError, match="nothing"):
        sim.linearize(["nothing"])


def test_a_restore_into_a_model_with_other_values_warns_naming_them():
    sim = monohydra.Simulation(FOURBAR)
    sim.advance(0.2)
    snap = sim.snapshot()
    sim.set_parameter("bodies/body3/mass", 60.0)
    with pytest.warns(monohydra.ModelWarning, match="mass 60 kg in this run, 50 kg in the snapshot"):
        sim.restore(snap)
    assert sim.time == pytest.approx(0.2)
