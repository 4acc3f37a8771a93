"""Writes assets/cam-torque.csv: the torque that turns a four-lobe camshaft
against its valve springs, over one revolution of the cam, every 2 degrees.

Valve-train model (direct-acting bucket followers, friction and valve-train
inertia left out, so the torque's mean over a revolution is zero):

- each lobe lifts its valve by h(phi) = L (1 - cos(2 pi phi / beta)) / 2 over
  beta = 120 cam degrees (a cosine, "harmonic", lift), L = 9 mm;
- the valve spring pushes the follower with F = F0 + k h, preload
  F0 = 250 N, rate k = 30 N/mm;
- power balance T omega = F dh/dt gives the torque on the cam
  T(phi) = F(h) dh/dphi (N m, with dh/dphi in m/rad): positive while the
  valve opens (the spring resists), negative while it closes (the spring
  drives the cam);
- four lobes 90 degrees apart (a four-cylinder engine's inlet camshaft,
  firing every 180 crank degrees), their torques summed.

The table is the torque needed to turn the cam in its running direction;
a scene gives it with load_table.scale = -1 on a counter-clockwise cam.
Run: python3 assets/cam_torque.py > assets/cam-torque.csv
"""
import math

LIFT_M = 0.009
DURATION_DEG = 120.0
PRELOAD_N = 250.0
RATE_N_M = 30e3
LOBES = 4


def lobe_torque(phi_deg):
    """Torque of one lobe whose opening starts at 0 degrees."""
    phi = phi_deg % 360.0
    if phi >= DURATION_DEG:
        return 0.0
    x = 2.0 * math.pi * phi / DURATION_DEG
    lift = 0.5 * LIFT_M * (1.0 - math.cos(x))
    dlift = 0.5 * LIFT_M * math.sin(x) * 2.0 * math.pi / math.radians(DURATION_DEG)
    return (PRELOAD_N + RATE_N_M * lift) * dlift


print("# Four-lobe camshaft against its valve springs (assets/cam_torque.py):")
print("# cosine lift 9 mm over 120 deg, spring 250 N + 30 N/mm, lobes 90 deg apart;")
print("# T = F dh/dphi, the torque needed to turn the cam (zero mean).")
print("angle_deg,torque_n_m")
for i in range(181):
    a = 2.0 * i
    t = sum(lobe_torque(a - 90.0 * j) for j in range(LOBES))
    print(f"{a:.1f},{t:.6f}")
