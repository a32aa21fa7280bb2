"""import monohydra (hosts/python): its results are the command line's CSV
byte for byte, a PI loop written in Python holds the four-bar's boom, snapshots
restore and pickle to the bit, errors carry the command line's messages, and
four threads give the serial results."""

import csv
import os
import pickle
import subprocess
import threading

import numpy as np
import pytest

import monohydra

SOURCE = os.environ["MH_SOURCE_DIR"]
EXECUTABLE = os.environ["MH_EXECUTABLE"]


def model(name):
    return os.path.join(SOURCE, "models", name)


def cli(*args):
    return subprocess.run([EXECUTABLE, *args], capture_output=True, text=True)


@pytest.mark.parametrize("name", ["fourbar.yaml", "quickreturn.yaml"])
@pytest.mark.parametrize("formulation", ["double-step", "penalty"])
def test_results_are_the_command_lines_csv_byte_for_byte(tmp_path, name, formulation):
    reference = tmp_path / "cli.csv"
    done = cli("run", model(name), "--formulation", formulation, "--out", str(reference))
    assert done.returncode == 0, done.stderr
    res = monohydra.Simulation(model(name), formulation=formulation).run()
    ours = tmp_path / "python.csv"
    res.to_csv(ours)
    assert ours.read_bytes() == reference.read_bytes()
    # The columns as NumPy arrays: the CSV's numbers, parsed back.
    table = np.loadtxt(reference, delimiter=",", skiprows=1)
    assert res.columns == reference.read_text().splitlines()[0].split(",")
    assert res["z1"].dtype == np.float64
    assert np.array_equal(res.t, table[:, 0])
    assert np.array_equal(res[res.columns[1]], table[:, 1])
    assert res.units["t"] == "s" and res.units["z1"] == "rad"


def test_a_python_pi_loop_on_the_valve_settles_within_1e4_metres():
    sim = monohydra.Simulation(model("fourbar.yaml"))
    sim.start()
    s0 = sim.value("s")
    kp, ki = 600.0, 500.0  # V/m, V/(m s): as models/fourbar-position-control.yaml
    integral, dt = 0.0, sim.dt
    while sim.time < 10.0 - 0.5 * dt:
        setpoint = 0.02 if sim.time >= 1.0 - 1e-9 else 0.0
        e = setpoint - (sim.value("s") - s0)
        v = kp * e + integral
        u = min(max(v, -10.0), 10.0)
        integral += dt * (ki * e + (u - v) * ki / kp)  # back-calculation, Tt = kp/ki
        sim.set_input("valve_command", u)
        sim.step()
    assert abs(sim.value("s") - s0 - 0.02) < 1e-4
    assert abs(sim.value("sdot")) < 1e-4


def test_snapshots_restore_and_pickle_to_the_bit(tmp_path):
    sim = monohydra.Simulation(model("fourbar.yaml"), formulation="penalty")
    sim.advance(4.0)
    snap = sim.snapshot()
    first = sim.run(10.0)
    again = pickle.loads(pickle.dumps(snap))
    assert again == snap
    sim.restore(again)
    assert sim.time == 4.0
    second = sim.run(10.0)
    assert np.array_equal(first._values, second._values)
    # In a fresh instance (as in another process: the bytes are all it gets).
    other = monohydra.Simulation(model("fourbar.yaml"), formulation="penalty")
    other.restore(pickle.loads(pickle.dumps(snap)))
    third = other.run(10.0)
    assert np.array_equal(first._values, third._values)
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    first.to_csv(a)
    third.to_csv(b)
    assert a.read_bytes().splitlines()[1:] == b.read_bytes().splitlines()[1:]


def test_a_snapshot_of_another_model_is_refused_with_the_reason():
    snap = monohydra.Simulation(model("fourbar.yaml")).snapshot()
    other = monohydra.Simulation(model("quickreturn.yaml"))
    with pytest.raises(monohydra.InputError, match="another"):
        other.restore(snap)
    with pytest.raises(monohydra.InputError):
        other.restore(monohydra.Snapshot(b"not a snapshot"))


def test_a_bad_model_raises_the_command_lines_message_with_file_and_line(tmp_path):
    text = open(model("fourbar.yaml")).read().replace("mass: 225", "mass: -225")
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    done = cli("validate", str(bad))
    assert done.returncode != 0
    message = done.stderr.strip().splitlines()[0].removeprefix("monohydra: ")
    assert str(bad) + ":" in message
    with pytest.raises(monohydra.InputError) as raised:
        monohydra.Simulation(str(bad))
    assert message in str(raised.value)
    assert isinstance(raised.value, monohydra.Error)


def test_unknown_names_and_bad_values_raise_input_error_naming_them():
    sim = monohydra.Simulation(model("fourbar.yaml"))
    sim.start()
    with pytest.raises(monohydra.InputError, match="'boom'"):
        sim.value("boom")
    with pytest.raises(monohydra.InputError, match="'boom'"):
        sim.set_input("boom", 1.0)
    with pytest.raises(monohydra.InputError, match="outside"):
        sim.set_input("valve_command", 11.0)
    with pytest.raises(monohydra.InputError):
        sim.set_input("valve_command", float("nan"))
    with pytest.raises(monohydra.InputError, match="formulation"):
        monohydra.Simulation(model("fourbar.yaml"), formulation="no-such-formulation")
    with pytest.raises(monohydra.InputError, match="subsystems/valve/no_such_option"):
        monohydra.Simulation(model("fourbar.yaml"), options={"subsystems/valve/no_such_option": 1})


def test_a_failed_run_raises_simulation_error_with_the_command_lines_message(tmp_path):
    # One Newton iteration per step cannot close the four-bar's loop once it moves.
    text = open(model("fourbar.yaml")).read().replace("max_iterations: 25", "max_iterations: 1")
    failing = tmp_path / "one-iteration.yaml"
    failing.write_text(text)
    done = cli("run", str(failing))
    assert done.returncode == 1
    line = [l for l in done.stderr.splitlines() if "simulation failed at " in l][0]
    message = line.split("simulation failed at ", 1)[1]
    sim = monohydra.Simulation(str(failing))
    with pytest.raises(monohydra.SimulationError, match=r"t = [0-9.e-]+ s, step [0-9]+") as raised:
        sim.run()
    assert message in str(raised.value)
    assert "converge" in str(raised.value)
    with pytest.raises(monohydra.SimulationError, match="restore a snapshot"):
        sim.step()


def test_four_threads_give_the_serial_results():
    def run(formulation):
        return monohydra.Simulation(model("fourbar.yaml"), formulation=formulation, t_end=3.0).run()

    formulations = ["double-step", "penalty", "double-step", "penalty"]
    serial = [run(f) for f in formulations]
    parallel = [None] * 4

    def work(k):
        parallel[k] = run(formulations[k])

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, parallel):
        assert np.array_equal(a._values, b._values)


def test_lists_inputs_outputs_and_columns_with_units_and_ranges():
    sim = monohydra.Simulation(model("fourbar.yaml"))
    (valve,) = sim.inputs
    assert valve.name == "valve_command" and valve.unit == "V" and valve.range == (-10.0, 10.0)
    assert "s" in [o.name for o in sim.outputs]
    assert [c.name for c in sim.coordinates] == ["z1", "z2", "z3"]
    assert sim.columns[0] == "t" and "p1" in sim.columns


def table_value(text, label, column):
    """A number of `monohydra compare`'s printed table: the row starting with
    `label`, its `column`-th value (0: the first run's)."""
    for line in text.splitlines():
        if line.startswith(label + " "):
            cells = line[len(label):].split()
            return float(cells[column])
    raise AssertionError(f"no row '{label}' in\n{text}")


def test_compare_gives_the_numbers_of_the_command_lines_table():
    done = cli("compare", model("fourbar.yaml"), "--formulations", "double-step,penalty",
               "--t-end", "3")
    assert done.returncode == 0, done.stderr
    table = monohydra.compare(model("fourbar.yaml"), formulations=["double-step", "penalty"],
                              t_end=3.0)
    assert [r["formulation"] for r in table] == ["double-step", "penalty"]
    for k, run in enumerate(table):
        column = 2 * k  # each run is followed by the paper's column
        assert run["status"] == "ok"
        assert run["steps"] == table_value(done.stdout, "steps", column) == 3000
        for label, key in [("Newton iterations avg", "avg_iterations"),
                           ("peak |drift| (J)", "peak_abs_drift"),
                           ("max |W| (J)", "max_abs_work"), ("max phi_norm", "max_phi_norm")]:
            printed = table_value(done.stdout, label, column)
            assert run[key] == pytest.approx(printed, rel=1e-3, abs=1e-12), label
    printed_dz = table_value(done.stdout, "max |dz| from double-step", 2)
    assert table[1]["max_abs_dz"] == pytest.approx(printed_dz, rel=1e-3)
    assert table[0]["max_abs_dz"] == 0.0
    assert table[1]["max_abs_dp"]["p1"] == pytest.approx(
        table_value(done.stdout, "max |dp1| from double-step (Pa)", 2), rel=1e-3)


def test_sweep_returns_the_study_table(tmp_path):
    study = os.path.join(SOURCE, "studies", "smoke.yaml")
    table = monohydra.sweep(study, jobs=2, out=tmp_path / "smoke")
    with open(tmp_path / "smoke" / "results.csv") as f:
        header = f.readline().strip().split(",")
    assert list(table) == header
    assert len(table["case"]) == 6
    assert list(table["status"]).count("ok") == 5  # the negative flow coefficient is refused
    assert table["peak_drift_J"].dtype == np.float64
    # The numbers are the file's, parsed independently.
    with open(tmp_path / "smoke" / "results.csv") as f:
        parsed = [float(r["max_p1"]) if r["max_p1"] else np.nan for r in csv.DictReader(f)]
    assert np.array_equal(table["max_p1"], np.array(parsed), equal_nan=True)
    assert table["formulation/name"][1] == "penalty"
    with pytest.raises(monohydra.InputError, match="no-such-study.yaml"):
        monohydra.sweep(tmp_path / "no-such-study.yaml")


def test_a_mass_set_in_place_is_the_model_opened_with_it():
    opened = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0,
                                  options={"bodies/body3/mass": 57.5}).run()
    sim = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0)
    sim.set_parameter("bodies/body3/mass", 57.5)
    changed = sim.run()
    assert np.array_equal(changed["z1"], opened["z1"])
    assert np.array_equal(changed["p1"], opened["p1"])
    nominal = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0).run()
    assert not np.array_equal(changed["z1"], nominal["z1"])


def test_a_component_option_set_in_place_is_the_model_opened_with_it():
    opened = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0,
                                  options={"subsystems/valve/flow_coefficient": 3e-8}).run()
    sim = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0)
    sim.set_parameter("subsystems/valve/flow_coefficient", 3e-8)
    changed = sim.run()
    assert np.array_equal(changed["z1"], opened["z1"])
    assert np.array_equal(changed["p1"], opened["p1"])


def test_an_initial_angle_set_before_start_is_the_model_opened_with_it():
    # The quick-return's crank (held at assembly) 5 degrees on: the loops
    # closed again around it, the same run to round-off (the cylinder took
    # its chamber lengths at the nominal start, which its equations cancel).
    opened = monohydra.Simulation(model("quickreturn.yaml"), t_end=1.0,
                                  options={"bodies/crank/z0": 35.59}).run()
    sim = monohydra.Simulation(model("quickreturn.yaml"), t_end=1.0)
    sim.set_parameter("bodies/crank/z0", 35.59)
    changed = sim.run()
    for column in ("z1", "z4", "p1"):
        scale = max(np.max(np.abs(opened[column])), 1.0)
        assert np.max(np.abs(changed[column] - opened[column])) < 1e-9 * scale
    nominal = monohydra.Simulation(model("quickreturn.yaml"), t_end=1.0).run()
    assert abs(nominal["z4"][0] - changed["z4"][0]) > 0.08  # 5 deg in rad
    with pytest.raises(monohydra.InputError, match="changes only before the run starts"):
        sim.set_parameter("bodies/crank/z0", 30.59)


def test_an_option_read_at_setup_or_a_bad_mass_set_in_place_raises_input_error():
    sim = monohydra.Simulation(model("fourbar.yaml"))
    with pytest.raises(monohydra.InputError, match="does not change 'length' in place"):
        sim.set_parameter("subsystems/cylinder/length", 1.2)
    with pytest.raises(monohydra.InputError, match=r"bodies\[2\].mass"):
        sim.set_parameter("bodies/body3/mass", -1.0)


def test_sensitivities_agree_with_two_runs_with_the_value_set():
    sens = monohydra.sensitivities(model("fourbar.yaml"), ["bodies/body3/mass", "gravity/1"],
                                   t_end=1.5)
    column = sens["d(p1)/d(bodies/body3/mass)"]
    assert sens["t"].shape == column.shape
    assert "d(z1)/d(gravity/1)" in sens
    delta = 0.05
    plus = monohydra.Simulation(model("fourbar.yaml"), t_end=1.5,
                                options={"bodies/body3/mass": 50.0 + delta}).run()
    minus = monohydra.Simulation(model("fourbar.yaml"), t_end=1.5,
                                 options={"bodies/body3/mass": 50.0 - delta}).run()
    differenced = (plus["p1"] - minus["p1"]) / (2 * delta)
    largest = np.max(np.abs(differenced))
    assert largest > 0
    assert np.max(np.abs(column - differenced)) < 1e-3 * largest


def test_sensitivities_of_a_parameter_it_cannot_take_raise_input_error():
    with pytest.raises(monohydra.InputError, match="does not change 'length' in place"):
        monohydra.sensitivities(model("fourbar.yaml"), ["subsystems/cylinder/length"], t_end=0.01)



def test_fit_recovers_a_mass_from_data_given_as_arrays():
    # The four-bar with its boom 15 % heavier, read without noise at 100 Hz
    # over 2 s: the fit from the nominal mass finds the heavier one.
    truth = monohydra.Simulation(model("fourbar.yaml"), t_end=2.0,
                                 options={"bodies/body1/mass": 258.75}).run()
    every = 10
    p1 = truth["p1"][::every].copy()
    p1[3] = np.nan  # a sample not taken
    result = monohydra.fit(model("fourbar.yaml"), {"t": truth["t"][::every], "p1": p1},
                           ["bodies/body1/mass"], noise={"p1": 3.8e4})
    assert list(result["path"]) == ["bodies/body1/mass"]
    assert result["initial"][0] == 225.0
    assert abs(result["estimate"][0] - 258.75) < 1e-3
    assert result["identifiable"][0]
    assert result["ci_low"][0] < 258.75 < result["ci_high"][0]


def test_fit_with_a_column_the_model_lacks_raises_input_error():
    with pytest.raises(monohydra.InputError, match="torque: a column of the model's"):
        monohydra.fit(model("fourbar.yaml"), {"t": [0.0, 0.1], "torque": [1.0, 2.0]},
                      ["bodies/body1/mass"])


def test_a_simulation_carries_the_derivatives_it_tracks():
    sim = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0)
    sim.track_sensitivities(["bodies/body3/mass", "gravity/1"])
    sim.run()
    d = sim.sensitivity("p1")
    assert d.shape == (2,)
    delta = 0.05
    plus = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0,
                                options={"bodies/body3/mass": 50.0 + delta}).run()
    minus = monohydra.Simulation(model("fourbar.yaml"), t_end=1.0,
                                 options={"bodies/body3/mass": 50.0 - delta}).run()
    differenced = (plus["p1"][-1] - minus["p1"][-1]) / (2 * delta)
    assert abs(d[0] - differenced) < 1e-3 * abs(differenced)
    with pytest.raises(monohydra.InputError, match="before it"):
        sim.track_sensitivities(["gravity/1"])
