#!/usr/bin/env python3
"""Reference integration of a bare rigid block under horizontal AND vertical pulses, written
independently of rocklab (scipy's solve_ivp, DOP853 at rtol 1e-12), for tests/vertical.rs.

Model (docs/MODEL.md "Vertical ground motion"): with pivot s = ±1 and g_eff = g + ü_v(t),
    θ̈ = −p² [ (g_eff/g) sin(sα − θ) + (ü_h/g) cos(sα − θ) ],
uplift from rest toward s = −sign(ü_h) when |ü_h| > g_eff tan α, Housner's impact
θ̇⁺ = √r θ̇⁻ with r = (1 − 1.5 sin²α)² at θ = 0 (pivot changes), and the block is put to rest
when |θ̇⁺| < √2e-10 · p · α (its next excursion would be < 1e-10 α), where it waits for the
ground to lift it again. Pulses are rocklab's: A sin(ωt) on 0 ≤ ωt ≤ 2π, zero elsewhere.

Usage: python3 scripts/vertical-reference.py > tests/data/vertical_reference.csv
(needs numpy and scipy: python3 -m venv /tmp/vref && /tmp/vref/bin/pip install scipy numpy)
"""

import math
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

G = 9.81
RTOL, ATOL = 1e-12, 1e-14


def sine(amplitude, omega):
    end = 2 * math.pi / omega

    def a(t):
        return amplitude * math.sin(omega * t) if 0.0 <= t <= end else 0.0

    return a, end


# name, alpha (rad), p (rad/s), horizontal (A/g, ω), vertical (A/g, ω), duration, sample step
CASES = [
    # Without the vertical pulse the ground (0.30 g < g tan α = 0.309 g) would not lift the
    # block; the vertical pulse's downward first lobe lowers g_eff and it does. It rocks
    # through ~80 impacts and comes to rest (chattering) after the ground stops.
    ("down_first", 0.3, 3.0, (0.30, 6.0), (-0.3, 5.0), 10.0, 0.02),
    # Upward first: a heavier block while the horizontal pulse first pushes, lighter later.
    ("up_first", 0.3, 3.0, (0.42, 6.0), (0.6, 4.0), 10.0, 0.02),
]


def simulate(alpha, p, hor, ver, duration):
    ah, h_end = sine(hor[0] * G, hor[1])
    av, v_end = sine(ver[0] * G, ver[1])
    p2 = p * p
    ta = math.tan(alpha)
    r = (1.0 - 1.5 * math.sin(alpha) ** 2) ** 2
    rest_rate = math.sqrt(2e-10) * p * alpha
    breaks = sorted({h_end, v_end})

    def geff(t):
        return G + av(t)

    def margin(t):
        return abs(ah(t)) - geff(t) * ta

    def rhs_for(s):
        def rhs(t, y):
            a = s * alpha - y[0]
            return [y[1], -p2 * (geff(t) / G * math.sin(a) + ah(t) / G * math.cos(a))]

        return rhs

    turns = []  # |θ| where θ̇ = 0 while rocking: the peaks
    pieces = []  # (t0, t1, dense or None for flat)
    events = []
    t, rocking, s, y = 0.0, False, 1.0, [0.0, 0.0]
    while t < duration:
        if not rocking:
            # Flat: the first time after t the ground lifts the block (a fine scan, then
            # bisection), or the end.
            grid = np.arange(t, min(duration, max(breaks) + 1e-9), 1e-4)
            found = None
            prev = (t, margin(t))
            if prev[1] > 0:
                found = t
            else:
                for tk in grid[1:]:
                    m = margin(tk)
                    if m > 0:
                        found = brentq(margin, prev[0], tk, xtol=1e-15, rtol=1e-15)
                        found = found if margin(found) > 0 else np.nextafter(found, np.inf)
                        while margin(found) <= 0:
                            found = np.nextafter(found, np.inf)
                        break
                    prev = (tk, m)
            if found is None:
                pieces.append((t, duration, None))
                break
            pieces.append((t, found, None))
            t = found
            s = -math.copysign(1.0, ah(t))
            y = [0.0, 0.0]
            rocking = True
            events.append((t, "uplift"))
            continue
        # Rocking on pivot s until an impact (sθ falls through 0) or overturning.
        stop = min([b for b in breaks if b > t + 1e-12] + [duration])

        def impact(tt, yy):
            return s * yy[0]

        impact.terminal, impact.direction = True, -1

        def overturn(tt, yy):
            return s * yy[0] - alpha

        overturn.terminal, overturn.direction = True, 1

        def turn(tt, yy):
            return yy[1]

        sol = solve_ivp(rhs_for(s), (t, stop), y, method="DOP853", rtol=RTOL, atol=ATOL,
                        events=[impact, overturn, turn], dense_output=True)
        for yt in sol.y_events[2]:
            turns.append(abs(yt[0]))
        if sol.t_events[1].size:
            te = sol.t_events[1][0]
            pieces.append((t, te, sol.sol))
            events.append((te, "overturn"))
            return pieces, events, te, float(alpha)
        if sol.t_events[0].size:
            te = sol.t_events[0][0]
            ye = sol.y_events[0][0]
            pieces.append((t, te, sol.sol))
            events.append((te, "impact"))
            t = te
            s = -s
            y = [0.0, ye[1] * math.sqrt(r)]
            if abs(y[1]) < rest_rate:
                rocking = False
                events.append((te, "rest"))
                # Lifted again at once if the ground asks for it.
            continue
        pieces.append((t, stop, sol.sol))
        t, y = stop, list(sol.y[:, -1])
    return pieces, events, duration, float(max(turns, default=0.0))


def theta_at(pieces, t):
    for t0, t1, dense in pieces:
        if t0 <= t <= t1:
            return 0.0 if dense is None else float(dense(t)[0])
    return 0.0


def main():
    out = sys.stdout
    out.write("# scripts/vertical-reference.py: bare rigid block, horizontal and vertical sine "
              "pulses (A/g, rad/s), scipy DOP853 rtol 1e-12\n")
    out.write("case,alpha,p,h_amplitude_g,h_omega,v_amplitude_g,v_omega,t,theta\n")
    for name, alpha, p, hor, ver, duration, dt in CASES:
        pieces, events, end, peak = simulate(alpha, p, hor, ver, duration)
        impacts = sum(1 for _, e in events if e == "impact")
        uplifts = sum(1 for _, e in events if e == "uplift")
        rests = sum(1 for _, e in events if e == "rest")
        print(f"{name}: {uplifts} uplifts, {impacts} impacts, {rests} rests, "
              f"peak θ/α {peak / alpha:.6f}, end {end}", file=sys.stderr)
        n = int(round(duration / dt))
        prefix = f"{name},{alpha},{p},{hor[0]},{hor[1]},{ver[0]},{ver[1]}"
        out.write(f"{prefix},peak,{peak!r}\n")
        for k in range(n + 1):
            t = k * dt
            out.write(f"{prefix},{t!r},{float(theta_at(pieces, t))!r}\n")


if __name__ == "__main__":
    main()
