"""monohydra.Estimator (hosts/python): fed a machine's sensor data it gives
`monohydra estimate`'s estimates, its noise is set by name, and every bad
call raises InputError, a filter that stops SimulationError."""

import csv
import math
import os
import subprocess

import numpy as np
import pytest

import monohydra

SOURCE = os.environ["MH_SOURCE_DIR"]
EXECUTABLE = os.environ["MH_EXECUTABLE"]
FOURBAR = os.path.join(SOURCE, "models", "fourbar.yaml")
MACHINE = ["--set", "bodies/body3/mass=55", "--set", "subsystems/cylinder/efficiency=0.76"]


def cli(*args):
    done = subprocess.run([EXECUTABLE, *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


def table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) if x else math.nan for x in r] for r in rows[1:]]


def test_an_estimator_fed_the_data_gives_the_estimate_commands_estimates(tmp_path):
    data, out = tmp_path / "data.csv", tmp_path / "estimated.csv"
    cli("run", FOURBAR, *MACHINE, "--t-end", "0.2", "--seed", "5", "--sensors-out", str(data),
        "--out", str(tmp_path / "truth.csv"))
    cli("estimate", FOURBAR, "--measurements", str(data), "--plant-noise", "p1=2e4",
        "--out", str(out))
    names, rows = table(data)
    header, expected = table(out)
    col = {name: k for k, name in enumerate(header)}
    sim = monohydra.Simulation(FOURBAR)
    est = monohydra.Estimator(sim, plant_noise={"p1": 2e4})
    assert est.sensors == names[1:]
    assert est.states[:3] == ["z3", "z3_dot", "p1"] and est.units["p1"] == "Pa"
    for row, want in zip(rows, expected):
        est.update(row[0], {n: v for n, v in zip(names[1:], row[1:]) if not math.isnan(v)})
        assert sim.time == pytest.approx(want[col["t"]], abs=1e-12)
        for name in est.states:
            assert est.sd(name) == pytest.approx(want[col[name + "_sd"]], rel=1e-9)
            if name in col:
                assert est[name] == pytest.approx(want[col[name]], rel=1e-9, abs=1e-15)
        assert sim.value("s") == pytest.approx(want[col["s"]], rel=1e-9)
        assert est.nis == pytest.approx(want[col["nis"]], rel=1e-8)
        assert est.innovation["z1"] == pytest.approx(want[col["z1_innovation"]], rel=1e-8, abs=1e-15)
    assert est.covariance.shape == (len(est.states), len(est.states))
    assert np.allclose(est.covariance, est.covariance.T)


def test_the_noise_set_by_name_is_the_initial_covariance():
    sim = monohydra.Simulation(FOURBAR)
    est = monohydra.Estimator(sim, filter="ukf", params=["subsystems/valve/flow_coefficient"],
                              initial_sd={"z3_dot": 0.01})
    assert est.states[-1] == "subsystems/valve/flow_coefficient"
    assert est.sd("z3_dot") == pytest.approx(0.01)
    assert est.sd("p1") == pytest.approx(1e5)  # the default of a pressure
    # A parameter starts at its model value, a fifth of it uncertain.
    assert est["subsystems/valve/flow_coefficient"] == pytest.approx(2.138e-8)
    assert est.sd("subsystems/valve/flow_coefficient") == pytest.approx(0.2 * 2.138e-8)
    assert math.isnan(est.nis)


def test_bad_estimator_calls_raise_input_error_and_a_stopped_filter_simulation_error():
    sim = monohydra.Simulation(FOURBAR)
    with pytest.raises(monohydra.InputError, match="filter 'pf': expected ekf or ukf"):
        monohydra.Estimator(sim, filter="pf")
    with pytest.raises(monohydra.InputError, match="bodies/nobody/mass"):
        monohydra.Estimator(sim, params=["bodies/nobody/mass"])
    with pytest.raises(monohydra.InputError, match="'z9' is not a state or parameter"):
        monohydra.Estimator(sim, plant_noise={"z9": 1.0})
    with pytest.raises(monohydra.InputError, match="expected a standard deviation of 0 or more"):
        monohydra.Estimator(sim, initial_sd={"p2": -1.0})
    quickreturn = monohydra.Simulation(os.path.join(SOURCE, "models", "quickreturn.yaml"))
    with pytest.raises(monohydra.InputError, match="has no sensors"):
        monohydra.Estimator(quickreturn)
    est = monohydra.Estimator(sim)
    with pytest.raises(monohydra.InputError, match="'torque' is not a sensor of the model"):
        est.update(0.001, {"torque": 1.0})
    with pytest.raises(monohydra.InputError, match="sensor 'z1': nan is not a finite number"):
        est.update(0.001, {"z1": float("nan")})
    est.update(0.01, {"z1": 0.0, "p1": None})
    with pytest.raises(monohydra.InputError, match="falls before the run's step"):
        est.update(0.005, {"z1": 0.0})
    with pytest.raises(monohydra.InputError, match="is not a finite time"):
        est.update(float("inf"), {"z1": 0.0})
    with pytest.raises(KeyError, match="no state 'z1'"):
        est["z1"]
    # Readings no state explains: the filter diverges, and takes no more.
    with pytest.raises(monohydra.SimulationError, match="the filter diverges"):
        for k in range(400):
            est.update(0.011 + 0.001 * k, {"z1": 2e-3 if k % 2 == 0 else -2e-3})
    with pytest.raises(monohydra.SimulationError, match="the filter stopped"):
        est.update(1.0, {"z1": 0.0})
