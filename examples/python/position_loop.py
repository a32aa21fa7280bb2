"""A PI controller written in Python moves the paper's four-bar boom to a
setpoint: it reads the cylinder's stroke every step and sets the valve's
command (the model's input valve_command) before the next one.

    PYTHONPATH=build/python python3 examples/python/position_loop.py

prints the settled error and, with matplotlib, writes
out/python/position-loop.png (docs/python.md shows it)."""

import os

import monohydra

sim = monohydra.Simulation("models/fourbar.yaml", t_end=10.0)
sim.start()
s0 = sim.value("s")  # m: the cylinder's length at the assembled start
kp, ki = 600.0, 500.0  # V/m, V/(m s)
integral, dt = 0.0, sim.dt
t, stroke, command = [], [], []
while sim.time < sim.t_end - 0.5 * dt:
    setpoint = 0.02 if sim.time >= 1.0 - 1e-9 else 0.0  # 20 mm out at t = 1 s
    e = setpoint - (sim.value("s") - s0)
    v = kp * e + integral
    u = min(max(v, -10.0), 10.0)  # the spool's range
    integral += dt * (ki * e + (u - v) * ki / kp)  # anti-windup: back-calculation
    sim.set_input("valve_command", u)
    sim.step()
    t.append(sim.time)
    stroke.append(1e3 * (sim.value("s") - s0))
    command.append(u)
print(f"stroke at t = {sim.time:g} s: {stroke[-1]:.4f} mm (setpoint 20 mm)")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    raise SystemExit(0)
fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 4.5))
top.plot(t, stroke, label="stroke")
top.axhline(20.0, color="grey", linestyle=":", label="setpoint")
top.set_ylabel("stroke change (mm)")
top.legend(loc="lower right")
bottom.plot(t, command, color="tab:red")
bottom.set_ylabel("valve command (V)")
bottom.set_xlabel("t (s)")
fig.suptitle("Four-bar boom under a PI loop written in Python")
fig.tight_layout()
os.makedirs("out/python", exist_ok=True)
fig.savefig("out/python/position-loop.png", dpi=100)
print("figure: out/python/position-loop.png")
