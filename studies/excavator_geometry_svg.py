#!/usr/bin/env python3
"""Draws the excavator's geometry (models/excavator.yaml) at its initial pose
as docs/figures/excavator-geometry.svg: a side view of the boom plane with
every joint and attachment point labelled, and a top view of the upper
carriage with the two boom cylinders and the slew cylinder.

usage: python3 studies/excavator_geometry_svg.py > docs/figures/excavator-geometry.svg

The points are the model file's numbers, repeated here (the drawing is
documentation, not an input); the rocker and link angles are the loop's
closure, computed as the host's assembly computes them.
"""
import math

D = math.radians
# Carriage frame: x forward, y left, z up; the boom plane is x-z.
A = (0.20, 0.90)        # boom foot (on the upper carriage)
LB, LA = 5.70, 2.90     # boom foot - arm pivot, arm pivot - bucket pivot
C = (1.00, 0.00)        # boom cylinders' feet (y = +-0.45)
PB = (2.40, -0.45)      # boom cylinders' eyes on the boom (boom frame)
AB = (2.60, 0.55)       # arm cylinder foot on the boom (boom frame)
HA = (-0.55, 0.35)      # arm cylinder eye on the arm, behind its pivot (arm frame)
BK = (0.35, 0.45)       # bucket cylinder foot on the arm (arm frame)
RO = (2.45, 0.10)       # rocker pivot on the arm (arm frame)
LR, LL = 0.60, 0.70     # rocker, link
KB = (-0.30, 0.30)      # link pin on the bucket (bucket frame)
TIP = (1.45, 0.0)       # bucket teeth (bucket frame), for the drawing
BOOM, ARM, BUCKET = 10.0, -60.0, -30.0   # initial relative angles (deg)


def rot(t, v):
    c, s = math.cos(t), math.sin(t)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1])


def pose():
    t1, t2 = D(BOOM), D(BOOM + ARM)
    t3 = t2 + D(BUCKET)
    p = {"A": A, "C": C}
    p["T1"] = add(A, rot(t1, (LB, 0)))
    p["T2"] = add(p["T1"], rot(t2, (LA, 0)))
    p["P"] = add(A, rot(t1, PB))
    p["F"] = add(A, rot(t1, AB))
    p["H"] = add(p["T1"], rot(t2, HA))
    p["Bf"] = add(p["T1"], rot(t2, BK))
    p["O"] = add(p["T1"], rot(t2, RO))
    p["K"] = add(p["T2"], rot(t3, KB))
    p["tip"] = add(p["T2"], rot(t3, TIP))
    o, k = p["O"], p["K"]
    dx, dz = k[0] - o[0], k[1] - o[1]
    d = math.hypot(dx, dz)
    a = (LR * LR - LL * LL + d * d) / (2 * d)
    h = math.sqrt(LR * LR - a * a)
    ex = (dx / d, dz / d)
    p["J"] = (o[0] + a * ex[0] - h * ex[1], o[1] + a * ex[1] + h * ex[0])
    return p


def main():
    p = pose()
    scale, ox, oz = 62.0, 230.0, 250.0   # px per m; origin (slew axis, ring height)
    X = lambda x: ox + scale * x
    Z = lambda z: oz - scale * z
    out = []
    w, h = 900, 700
    out.append(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
               f'viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">')
    out.append(f'<rect width="{w}" height="{h}" fill="#ffffff"/>')
    out.append('<text x="450" y="20" text-anchor="middle" font-weight="bold">'
               'Excavator (models/excavator.yaml) at t = 0: side view of the boom plane '
               '(x forward, z up, m)</text>')

    def line(a, b, colour, width, dash=""):
        d = f' stroke-dasharray="{dash}"' if dash else ""
        out.append(f'<line x1="{X(a[0]):.1f}" y1="{Z(a[1]):.1f}" x2="{X(b[0]):.1f}" '
                   f'y2="{Z(b[1]):.1f}" stroke="{colour}" stroke-width="{width}" '
                   f'stroke-linecap="round"{d}/>')

    def label(name, q, dx=6, dy=-6):
        out.append(f'<circle cx="{X(q[0]):.1f}" cy="{Z(q[1]):.1f}" r="3.5" fill="#ffffff" '
                   f'stroke="#000000"/>')
        out.append(f'<text x="{X(q[0]) + dx:.1f}" y="{Z(q[1]) + dy:.1f}">{name}</text>')

    # upper carriage outline, ground level (1.1 m below the slew ring), slew axis
    out.append(f'<rect x="{X(-3.0):.1f}" y="{Z(2.0):.1f}" width="{scale * 4.2:.1f}" '
               f'height="{scale * 2.0:.1f}" fill="#eef2f8" stroke="#9aaac4"/>')
    out.append(f'<text x="{X(-2.9):.1f}" y="{Z(1.75):.1f}" fill="#5a6a84">upper carriage '
               f'8500 kg (counterweight behind)</text>')
    line((0, -1.1), (0, 2.6), "#777777", 1, "6 4")
    out.append(f'<text x="{X(0.05):.1f}" y="{Z(2.45):.1f}" fill="#555555">slew axis z1</text>')
    line((-3.5, -1.1), (10.0, -1.1), "#8b6f47", 1.5)
    out.append(f'<text x="{X(-3.4):.1f}" y="{Z(-1.25):.1f}" fill="#8b6f47">ground '
               f'(1.1 m below the slew ring)</text>')
    # bodies
    body = "#1f3b73"
    line(p["A"], p["T1"], body, 4)
    line(p["A"], p["P"], body, 2)
    line(p["P"], p["T1"], body, 2)
    line(p["A"], p["F"], body, 2)
    line(p["F"], p["T1"], body, 2)
    line(p["H"], p["T2"], body, 4)
    line(p["T2"], p["K"], body, 3)
    line(p["T2"], p["tip"], body, 4)
    line(p["K"], p["tip"], body, 2)
    line(p["O"], p["J"], "#3d6bb3", 3)
    line(p["J"], p["K"], "#3d6bb3", 3)
    # cylinders
    cyl = "#c0600b"
    line(p["C"], p["P"], cyl, 6)
    line(p["F"], p["H"], cyl, 6)
    line(p["Bf"], p["J"], cyl, 6)
    for name, key, dx, dy in [("A boom foot", "A", -80, -8), ("C boom cyl. feet", "C", 6, 16),
                              ("P boom cyl. eyes (spherical cuts)", "P", 8, 14),
                              ("F arm cyl. foot", "F", -30, -10),
                              ("T1 arm pivot", "T1", 8, -6), ("H arm cyl. eye", "H", 8, -8),
                              ("B bucket cyl. foot", "Bf", 8, 14), ("O rocker pivot", "O", -100, 4),
                              ("J rocker-link pin", "J", 8, -6),
                              ("K link pin (spherical cut)", "K", 8, 4),
                              ("T2 bucket pivot", "T2", -105, 10), ("teeth", "tip", 8, 4)]:
        label(name, p[key], dx, dy)
    out.append(f'<text x="{X(1.7):.1f}" y="{Z(0.05):.1f}" fill="{cyl}">2 boom cylinders '
               f'(z7-z10)</text>')
    out.append(f'<text x="{X(3.7):.1f}" y="{Z(2.55):.1f}" fill="{cyl}">arm cylinder</text>')
    out.append(f'<text x="{X(5.9):.1f}" y="{Z(0.95):.1f}" fill="{cyl}">bucket cylinder</text>')
    out.append(f'<text x="{X(3.0):.1f}" y="{Z(1.9):.1f}" fill="{body}">boom z2 '
               f'({BOOM:g} deg)</text>')
    out.append(f'<text x="{X(2.2):.1f}" y="{Z(-1.7):.1f}" fill="{body}">arm z3 ({ARM:g} deg), '
               f'bucket z4 ({BUCKET:g} deg), rocker z5, link z6</text>')

    # top view of the carriage (x forward, y left): boom cylinders at y = +-0.45,
    # slew cylinder from the undercarriage to a crank on the carriage.
    s2, ox2, oy2 = 60.0, 260.0, 560.0
    XT = lambda x: ox2 + s2 * x
    YT = lambda y: oy2 - s2 * y
    out.append(f'<text x="30" y="{oy2 - 110}" font-weight="bold">Top view of the upper '
               f'carriage at t = 0 (x forward, y left)</text>')
    out.append(f'<rect x="{XT(-3.0):.1f}" y="{YT(1.4):.1f}" width="{s2 * 4.2:.1f}" '
               f'height="{s2 * 2.8:.1f}" fill="#eef2f8" stroke="#9aaac4"/>')

    def tline(a, b, colour, width):
        out.append(f'<line x1="{XT(a[0]):.1f}" y1="{YT(a[1]):.1f}" x2="{XT(b[0]):.1f}" '
                   f'y2="{YT(b[1]):.1f}" stroke="{colour}" stroke-width="{width}" '
                   f'stroke-linecap="round"/>')

    def tlabel(text, q, dx=6, dy=-6):
        out.append(f'<circle cx="{XT(q[0]):.1f}" cy="{YT(q[1]):.1f}" r="3.5" fill="#ffffff" '
                   f'stroke="#000000"/>')
        out.append(f'<text x="{XT(q[0]) + dx:.1f}" y="{YT(q[1]) + dy:.1f}">{text}</text>')

    tline((0.2, 0.0), (0.2 + LB * math.cos(D(BOOM)), 0.0), body, 4)
    for y in (0.45, -0.45):
        tline((1.0, y), (p["P"][0], y), cyl, 6)
    crank = (0.8 * math.cos(D(-120)), 0.8 * math.sin(D(-120)))
    g = (-2.0, -0.8)
    tline((0, 0), crank, body, 2)
    tline(g, crank, cyl, 6)
    tlabel("slew axis", (0, 0), 6, -8)
    tlabel("boom cyl. left (y = +0.45)", (1.0, 0.45), 6, -8)
    tlabel("boom cyl. right (y = -0.45)", (1.0, -0.45), 6, 16)
    tlabel("slew cyl. foot (-2.0, -0.8, 0.3), undercarriage", g, -100, 34)
    tlabel("crank (-0.4, -0.693, 0.3), r = 0.8 m", crank, 6, 30)
    out.append(f'<text x="{XT(3.0):.1f}" y="{YT(0.15):.1f}" fill="{body}">boom (to 5.9 m)</text>')
    out.append("</svg>")
    print("\n".join(out))


if __name__ == "__main__":
    main()
